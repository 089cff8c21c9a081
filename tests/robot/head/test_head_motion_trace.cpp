// SPDX-License-Identifier: MIT
/// @brief Head-motion trace: start/finish latencies from known shifts, CSV and PNG output.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "robot/head/head_motion_trace.h"

namespace telesphere::robot {
namespace {

/// A trapezoidal speed profile rising at `start`, falling to 0 at `end` (s).
double trapezoid(double t, double start, double end) {
  const double ramp = 0.1;
  if (t <= start || t >= end) return 0.0;
  return 0.5 * std::min({1.0, (t - start) / ramp, (end - t) / ramp});
}

std::vector<head::HeadMotionSample> syntheticTrace() {
  std::vector<head::HeadMotionSample> trace;
  for (int k = 0; k <= 300; ++k) {
    const double t = k * 0.01;
    trace.push_back({t, trapezoid(t, 0.5, 1.6), trapezoid(t, 0.63, 1.7), 0.01 * std::sin(t)});
  }
  return trace;
}

TEST(HeadMotionTrace, LatenciesFromThresholdCrossings) {
  const head::HeadLatencies l = head::measureHeadLatencies(syntheticTrace(), 0.05);
  ASSERT_TRUE(l.start_s && l.finish_s);
  EXPECT_NEAR(*l.start_s, 0.13, 1e-9);
  EXPECT_NEAR(*l.finish_s, 0.10, 1e-9);
  const head::HeadLatencies never = head::measureHeadLatencies(syntheticTrace(), 0.9);
  EXPECT_FALSE(never.start_s);
  EXPECT_FALSE(never.finish_s);
}

TEST(HeadMotionTrace, WritesCsv) {
  const std::filesystem::path dir =
      std::filesystem::path(TELESPHERE_BINARY_DIR) / "test-out" / "head_motion_trace";
  std::filesystem::create_directories(dir);
  const std::vector<head::HeadMotionSample> trace = syntheticTrace();
  ASSERT_TRUE(head::writeHeadMotionCsv(dir / "trace.csv", trace));
  std::ifstream csv(dir / "trace.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "t_s,v_operator,v_robot,deviation");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, static_cast<int>(trace.size()));

  EXPECT_FALSE(head::writeHeadMotionCsv(dir / "no-such-dir" / "x.csv", trace));
}

}  // namespace
}  // namespace telesphere::robot
