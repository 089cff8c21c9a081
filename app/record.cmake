# SPDX-License-Identifier: MIT
# telesphere-mcap: what a recording holds (summary), and finishing a cut-off one (recover).
if(TARGET telesphere::record)
  add_executable(telesphere-mcap telesphere_mcap.cpp)
  target_include_directories(telesphere-mcap PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(telesphere-mcap PRIVATE telesphere::record CLI11::CLI11 nlohmann_json::nlohmann_json
    telesphere_warnings)
endif()
