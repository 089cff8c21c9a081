# SPDX-License-Identifier: MIT
# @brief telesphere::camera_models: the camera models (ds, eucm, kb4, pinhole-radtan: header-only
#        templates) and GenericCamera, which holds any of them. Eigen only. Included by
#        calib/CMakeLists.txt and by the travelling render benchmark (app/bench/render_travel/).
add_library(telesphere_camera_models ${CMAKE_CURRENT_LIST_DIR}/generic_camera.cpp)
add_library(telesphere::camera_models ALIAS telesphere_camera_models)
get_filename_component(telesphere_camera_models_root ${CMAKE_CURRENT_LIST_DIR}/.. ABSOLUTE)
target_include_directories(telesphere_camera_models PUBLIC ${telesphere_camera_models_root})
target_link_libraries(telesphere_camera_models PUBLIC Eigen3::Eigen)
if(TARGET telesphere_warnings)
  target_link_libraries(telesphere_camera_models PRIVATE telesphere_warnings)
endif()
