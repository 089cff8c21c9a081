// SPDX-License-Identifier: MIT
/// @brief telesphere-bench: measures every speed/accuracy knob, one subcommand per topic.
///        `telesphere-bench TOPIC [--quick] [--json] [topic options]`; tables on stdout, or with
///        --json the figures as one JSON object on stdout (tables then go to stderr).
#include <CLI/CLI.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "app/bench/bench_topic.h"

int main(int argc, char** argv) {
  using telesphere::bench::benchTopics;
  CLI::App app{"telesphere-bench: speed and accuracy of every knob, as tables"};
  app.require_subcommand(1);
  bool quick = false;
  bool json = false;
  app.add_flag("--quick", quick, "CI-sized run (fewer samples)");
  app.add_flag("--json", json, "print the figures as one JSON object instead of tables");
  for (const auto& topic : benchTopics()) {
    CLI::App* sub = app.add_subcommand(topic.name, topic.description);
    sub->add_flag("--quick", quick, "CI-sized run (fewer samples)");
    sub->add_flag("--json", json, "print the figures as one JSON object instead of tables");
    if (topic.add_options) topic.add_options(*sub);
  }
  CLI11_PARSE(app, argc, argv);
  // Library log lines (the link's, …) go to stderr: stdout carries only tables or the JSON.
  spdlog::set_default_logger(spdlog::stderr_color_mt("telesphere-bench"));
  for (const auto& topic : benchTopics()) {
    if (!app.got_subcommand(topic.name)) continue;
    try {
      const telesphere::bench::BenchContext context{quick, json ? std::cerr : std::cout};
      const nlohmann::json figures = topic.run(context);
      if (json) std::cout << figures.dump(2) << std::endl;
      return 0;
    } catch (const std::exception& e) {
      std::cerr << "telesphere-bench " << topic.name << ": " << e.what() << std::endl;
      return 1;
    }
  }
  return 2;
}
