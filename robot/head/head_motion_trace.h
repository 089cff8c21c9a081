// SPDX-License-Identifier: MIT
/// @brief The head-latency experiment of the paper's Fig. 6 as data: operator and robot head speed
///        and their deviation over time, the start/finish latencies read from them, and the CSV
///        they are written as (the figure: telesphere-bench, head_motion_figure.h).
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

namespace telesphere::robot::head {

/// One instant of a replayed head motion.
struct HeadMotionSample {
  double t_s = 0;         ///< s since the start of the replay
  double v_operator = 0;  ///< m/s, speed of the operator's head mapped into the robot frame
  double v_robot = 0;     ///< m/s, speed of the robot head (from measured joint states)
  double deviation = 0;   ///< m, Δs: |operator eye − robot camera| (left eye, cam_l)
};

/// Start and finish latency (paper Fig. 6): with a speed threshold v_thr,
///   t1 = (first t with v_robot ≥ v_thr) − (first t with v_operator ≥ v_thr),
///   t2 = (last t with v_robot ≥ v_thr) − (last t with v_operator ≥ v_thr),
/// each crossing interpolated linearly between samples. Empty where a speed never crosses.
struct HeadLatencies {
  std::optional<double> start_s, finish_s;
};
HeadLatencies measureHeadLatencies(const std::vector<HeadMotionSample>& trace, double v_thr);

/// Writes `t_s,v_operator,v_robot,deviation` rows with a header line. False on an I/O error.
bool writeHeadMotionCsv(const std::filesystem::path& path,
                        const std::vector<HeadMotionSample>& trace);

}  // namespace telesphere::robot::head
