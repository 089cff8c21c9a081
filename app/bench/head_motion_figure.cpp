// SPDX-License-Identifier: MIT
/// @brief The head-latency figure (see head_motion_figure.h).
#include "app/bench/head_motion_figure.h"

#include <cmath>

namespace telesphere::bench {

Figure headMotionFigure(const std::vector<robot::head::HeadMotionSample>& trace, const std::string& title) {
  FigureSeries op{"operator head speed v_op", {}, {}, QColor(31, 119, 180)};
  FigureSeries rob{"robot head speed v_rob", {}, {}, QColor(214, 39, 40)};
  FigureSeries ds{"Δs, left eye to left camera (right axis)", {}, {}, QColor(44, 160, 44)};
  ds.right_axis = true;
  for (const robot::head::HeadMotionSample& s : trace) {
    op.x.push_back(s.t_s), op.y.push_back(s.v_operator);
    rob.x.push_back(s.t_s), rob.y.push_back(s.v_robot);
    if (std::isfinite(s.deviation)) ds.x.push_back(s.t_s), ds.y.push_back(s.deviation * 1e3);
  }
  Figure figure{title, "time (s)", "head speed (m/s)", "Δs, eye to camera (mm)", {op, rob, ds}};
  figure.legend_left = true;
  return figure;
}

}  // namespace telesphere::bench
