// SPDX-License-Identifier: MIT
/// @brief The supervisor's live graphs (the paper's figures, live): image latency per stage
///        stacked (§IV-A, 40 ms); head pose → robot latency; operator and robot head speed
///        (Fig. 6); Δs with v_op (Fig. 7); XR frame time and missed frames; the operator's scene
///        proxy: each eye's radius with each camera's stereo-depth confidence, and the depth's age
///        and sweep time (#35). Which series, how drawn, with axes and units (one unit an axis).
#pragma once

#include <vector>

#include "console/widgets/live_plot.h"

namespace telesphere::console {

std::vector<PlotSpec> supervisorPlots();

}  // namespace telesphere::console
