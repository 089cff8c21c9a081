# SPDX-License-Identifier: MIT
# telesphere-console: the supervisor's Qt console (console/).
if(TARGET telesphere::console)
  add_executable(telesphere-console telesphere_console.cpp console_study_command.cpp
    console_calibrate_command.cpp console_calibrate_run.cpp console_calibrate_handeye.cpp console_robot_commands.cpp
    link_security_options.cpp)
  target_link_libraries(telesphere-console PRIVATE telesphere::console telesphere::console_study telesphere::console_calibration
    nlohmann_json::nlohmann_json CLI11::CLI11
    telesphere_warnings)
endif()
