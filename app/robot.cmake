# SPDX-License-Identifier: MIT
# telesphere-robot: cameras, head arm and link server (the robot side).
if(TARGET telesphere::robot)
  add_executable(telesphere-robot telesphere_robot.cpp robot_options.cpp robot_assembly.cpp)
  target_include_directories(telesphere-robot PRIVATE ${PROJECT_SOURCE_DIR})
  target_compile_definitions(telesphere-robot PRIVATE TELESPHERE_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  target_link_libraries(telesphere-robot PRIVATE telesphere::robot CLI11::CLI11 telesphere_warnings)
endif()
