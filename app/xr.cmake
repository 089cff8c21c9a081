# SPDX-License-Identifier: MIT
# telesphere-xr: the operator's renderer. For now the `still` command (one eye view to PNG).
if(TARGET telesphere::xr)
  find_package(OpenCV REQUIRED COMPONENTS core imgcodecs imgproc)
  add_executable(telesphere-xr telesphere_xr.cpp)
  target_include_directories(telesphere-xr SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  target_link_libraries(telesphere-xr PRIVATE telesphere::xr telesphere::gl CLI11::CLI11
    opencv_core opencv_imgcodecs opencv_imgproc telesphere_warnings)
endif()
