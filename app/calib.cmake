# SPDX-License-Identifier: MIT
# telesphere-calib: calibration and camera-model tools.
if(TARGET telesphere_calib)
  add_executable(telesphere-calib telesphere_calib.cpp)
  target_link_libraries(telesphere-calib PRIVATE telesphere::calib CLI11::CLI11 telesphere_warnings)
endif()
