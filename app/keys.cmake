# SPDX-License-Identifier: MIT
# telesphere-keys: key pairs for the link's programs, with their role (DESIGN.md §10).
if(TARGET telesphere::link_trust)
  add_executable(telesphere-keys telesphere_keys.cpp)
  target_include_directories(telesphere-keys PRIVATE ${PROJECT_SOURCE_DIR})
  target_link_libraries(telesphere-keys PRIVATE telesphere::link_trust CLI11::CLI11 telesphere_warnings)
endif()
