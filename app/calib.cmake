# SPDX-License-Identifier: MIT
# telesphere-calib: calibration and camera-model tools.
if(TARGET telesphere_calib)
  add_executable(telesphere-calib telesphere_calib.cpp calib_file_commands.cpp calib_intrinsics_command.cpp
    calib_handeye_command.cpp)
  target_link_libraries(telesphere-calib PRIVATE telesphere::calib CLI11::CLI11 telesphere_warnings)
  # Hand-eye sample files with head-arm joint angles use the xArm 6 forward kinematics.
  if(TARGET telesphere_robot)
    target_link_libraries(telesphere-calib PRIVATE telesphere::robot)
    target_compile_definitions(telesphere-calib PRIVATE TELESPHERE_CALIB_HAS_ROBOT)
  endif()
endif()
