# SPDX-License-Identifier: MIT
# telesphere-bench (one subcommand per topic, tables or --json), telesphere-render-bench and
# telesphere-truth-check: app/bench/.
add_subdirectory(${CMAKE_CURRENT_SOURCE_DIR}/bench ${CMAKE_CURRENT_BINARY_DIR}/bench)
