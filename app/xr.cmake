# SPDX-License-Identifier: MIT
# telesphere-xr: the operator's renderer: `still` (one eye view to PNG) and `openxr` (an OpenXR
# session against a headset or Monado, xr/README.md "OpenXR session").
if(TARGET telesphere::xr_frame_loop)
  find_package(OpenCV REQUIRED COMPONENTS core imgcodecs imgproc)
  add_executable(telesphere-xr telesphere_xr.cpp xr_offscreen_command.cpp xr_openxr_command.cpp xr_desktop_command.cpp
    xr_video_link_options.cpp xr_depth_options.cpp link_security_options.cpp)
  target_include_directories(telesphere-xr SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  target_include_directories(telesphere-xr PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(telesphere-xr PRIVATE nlohmann_json::nlohmann_json telesphere::xr_frame_loop telesphere::xr_replay telesphere::xr_openxr telesphere::xr_desktop telesphere::gl CLI11::CLI11
    opencv_core opencv_imgcodecs opencv_imgproc telesphere_warnings)
endif()
