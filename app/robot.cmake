# SPDX-License-Identifier: MIT
# telesphere-robot: cameras, head arm and link server (the robot side); telesphere-xarm-sim: a
# simulated xArm controller on the real protocol (rehearsing --arm xarm without the arm).
if(TARGET telesphere::robot)
  add_executable(telesphere-robot telesphere_robot.cpp robot_options.cpp robot_assembly.cpp robot_assembly_parts.cpp robot_replay.cpp
    link_security_options.cpp)
  target_include_directories(telesphere-robot PRIVATE ${PROJECT_SOURCE_DIR})
  target_compile_definitions(telesphere-robot PRIVATE TELESPHERE_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  target_link_libraries(telesphere-robot PRIVATE telesphere::robot telesphere::record CLI11::CLI11 telesphere_warnings)
endif()
if(TARGET telesphere::xarm_sim)
  add_executable(telesphere-xarm-sim telesphere_xarm_sim.cpp)
  target_link_libraries(telesphere-xarm-sim PRIVATE telesphere::xarm_sim CLI11::CLI11 telesphere_warnings)
endif()
