# SPDX-License-Identifier: MIT
# telesphere-bench: one subcommand per topic (tests/bench/), tables or --json.
if(TELESPHERE_BUILD_TESTS AND NOT TELESPHERE_USE_DEMO_TREE)  # else the demo tree's is run
  get_property(bench_topics GLOBAL PROPERTY TELESPHERE_BENCH_TOPICS)
  add_executable(telesphere-bench telesphere_bench.cpp)
  target_link_libraries(telesphere-bench PRIVATE telesphere_bench_core ${bench_topics} spdlog::spdlog
    telesphere_warnings)
endif()
