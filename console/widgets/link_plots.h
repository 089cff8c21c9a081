// SPDX-License-Identifier: MIT
/// @brief The Internet link's live graphs (DESIGN.md §9): the media path's rate (delivered, target,
///        cap), its delays (round trip, queue, frame age), loss against repair, and the stream
///        settings the rate allows. Which series, how drawn, with axes and units.
#pragma once

#include <vector>

#include "console/widgets/live_plot.h"

namespace telesphere::console {

std::vector<PlotSpec> linkPlots();

}  // namespace telesphere::console
