// SPDX-License-Identifier: MIT
/// @brief Head-motion trace analysis and writers (see head_motion_trace.h).
#include "robot/head/head_motion_trace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>

namespace telesphere::robot::head {
namespace {

/// Time at which `value` crosses v_thr upwards first (first = true) or downwards last.
std::optional<double> crossing(const std::vector<HeadMotionSample>& trace, double v_thr,
                               const std::function<double(const HeadMotionSample&)>& value,
                               bool first) {
  const std::size_t n = trace.size();
  for (std::size_t k = 1; k < n; ++k) {
    const std::size_t i = first ? k : n - k;  // segment [i−1, i]
    const double a = value(trace[i - 1]), b = value(trace[i]);
    const bool crosses = first ? (a < v_thr && b >= v_thr) : (a >= v_thr && b < v_thr);
    if (!crosses) continue;
    const double s = (v_thr - a) / (b - a);
    return trace[i - 1].t_s + s * (trace[i].t_s - trace[i - 1].t_s);
  }
  return std::nullopt;
}

}  // namespace

HeadLatencies measureHeadLatencies(const std::vector<HeadMotionSample>& trace, double v_thr) {
  const auto op = [](const HeadMotionSample& s) { return s.v_operator; };
  const auto rob = [](const HeadMotionSample& s) { return s.v_robot; };
  HeadLatencies out;
  const auto op_start = crossing(trace, v_thr, op, true), rob_start = crossing(trace, v_thr, rob, true);
  const auto op_end = crossing(trace, v_thr, op, false), rob_end = crossing(trace, v_thr, rob, false);
  if (op_start && rob_start) out.start_s = *rob_start - *op_start;
  if (op_end && rob_end) out.finish_s = *rob_end - *op_end;
  return out;
}

bool writeHeadMotionCsv(const std::filesystem::path& path,
                        const std::vector<HeadMotionSample>& trace) {
  std::ofstream out(path);
  if (!out) return false;
  out << "t_s,v_operator,v_robot,deviation\n";
  char line[160];
  for (const HeadMotionSample& s : trace) {
    std::snprintf(line, sizeof line, "%.4f,%.6f,%.6f,%.6f\n", s.t_s, s.v_operator, s.v_robot,
                  s.deviation);
    out << line;
  }
  return static_cast<bool>(out);
}

}  // namespace telesphere::robot::head
