// SPDX-License-Identifier: MIT
/// @brief The head-latency trace (paper Fig. 6) as a figure: operator and robot head speed (m/s,
///        left axis) and Δs, eye to camera (mm, right axis), over time (s), with a legend; the same
///        figure for `telesphere-bench head` (and so the demo's head/head_latency.png) and the
///        experiments' fig6_head_latency.png.
#pragma once

#include <string>
#include <vector>

#include "robot/head/head_motion_trace.h"
#include "app/bench/figure_png.h"

namespace telesphere::bench {

Figure headMotionFigure(const std::vector<robot::head::HeadMotionSample>& trace, const std::string& title);

}  // namespace telesphere::bench
