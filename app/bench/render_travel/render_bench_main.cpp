// SPDX-License-Identifier: MIT
/// @brief telesphere-render-bench: the `render` and `upload` topics of telesphere-bench as a
///        program of its own that can be copied to a machine with a GPU (see CMakeLists.txt
///        beside it): `telesphere-render-bench [render|upload] [--quick] [--json]`, both topics
///        when none is named; the same tables, and with --json one object per topic.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/bench/bench_topic.h"

int main(int argc, char** argv) {
  CLI::App app{"telesphere-render-bench: the spherical renderer's paths at headset resolutions (ms per "
               "stereo frame, error against the double-precision reference) and a camera frame's upload"};
  bool quick = false;
  bool json = false;
  std::vector<std::string> names;
  app.add_flag("--quick", quick, "CI-sized run (fewer frames, the paper's headset only)");
  app.add_flag("--json", json, "print the figures as one JSON object (the tables go to stderr)");
  app.add_option("topics", names, "render, upload (default: both)");
  CLI11_PARSE(app, argc, argv);
  nlohmann::json figures = nlohmann::json::object();
  for (const auto& topic : telesphere::bench::benchTopics()) {
    if (!names.empty() && std::find(names.begin(), names.end(), topic.name) == names.end()) continue;
    try {
      const telesphere::bench::BenchContext context{quick, json ? std::cerr : std::cout};
      figures[topic.name] = topic.run(context);
    } catch (const std::exception& e) {
      std::cerr << "telesphere-render-bench " << topic.name << ": " << e.what() << std::endl;
      return 1;
    }
  }
  if (figures.empty()) {
    std::cerr << "telesphere-render-bench: no such topic (render, upload)" << std::endl;
    return 2;
  }
  if (json) std::cout << figures.dump(2) << std::endl;
  return 0;
}
