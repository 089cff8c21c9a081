# SPDX-License-Identifier: MIT
# @brief telesphere::xr_virtual_head (the keyboard/mouse-driven head pose, pure maths, testable
#        without a window) and telesphere::xr_desktop (the GLFW window with an EGL-created GL
#        4.5 core context for desktop mode and the headset mirror).
add_library(telesphere_xr_virtual_head virtual_head.cpp)
add_library(telesphere::xr_virtual_head ALIAS telesphere_xr_virtual_head)
target_include_directories(telesphere_xr_virtual_head PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(telesphere_xr_virtual_head
  PUBLIC Eigen3::Eigen
  PRIVATE telesphere_warnings)

find_package(glfw3 3.3 REQUIRED)
add_library(telesphere_xr_desktop desktop_window.cpp)
add_library(telesphere::xr_desktop ALIAS telesphere_xr_desktop)
target_include_directories(telesphere_xr_desktop PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(telesphere_xr_desktop
  PUBLIC telesphere::xr_virtual_head telesphere::gl
  PRIVATE glfw telesphere_warnings)
