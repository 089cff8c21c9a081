// SPDX-License-Identifier: MIT
/// @brief One `telesphere-bench` subcommand per topic (DESIGN.md §1): a topic registers itself
///        with TELESPHERE_BENCH_TOPIC, adds its own options to its CLI11 subcommand, prints its
///        tables to `out` and returns its figures as JSON (what `--json` prints).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace telesphere::bench {

/// What every topic gets when it runs.
struct BenchContext {
  bool quick = false;  ///< CI-sized run: fewer samples, smaller sizes
  std::ostream& out;   ///< where tables and progress go (stderr under --json)
};

struct BenchTopic {
  std::string name;
  std::string description;
  std::function<void(CLI::App& subcommand)> add_options;  ///< may be empty
  std::function<nlohmann::json(const BenchContext&)> run;
};

/// All topics linked into the executable, in registration order.
std::vector<BenchTopic>& benchTopics();

struct BenchTopicRegistration {
  explicit BenchTopicRegistration(BenchTopic topic) { benchTopics().push_back(std::move(topic)); }
};

}  // namespace telesphere::bench

/// TELESPHERE_BENCH_TOPIC(id, BenchTopic{...}) at namespace scope in a topic's .cpp.
#define TELESPHERE_BENCH_TOPIC(id, ...) \
  static const ::telesphere::bench::BenchTopicRegistration telesphere_bench_topic_##id(__VA_ARGS__)
