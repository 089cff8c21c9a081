// SPDX-License-Identifier: MIT
/// @brief supervisorPlots: the seven plot specifications.
#include "console/widgets/supervisor_plots.h"

#include "console/telemetry/telemetry_model.h"

namespace telesphere::console {

std::vector<PlotSpec> supervisorPlots() {
  std::vector<PlotSpec> plots;
  {
    // Cumulative latency since capture per stage: each band is one stage's share.
    PlotSpec p{"Image latency per stage", "latency since capture [ms]", "", {}};
    const char* stage_names[] = {"encode", "send", "link", "decode", "upload", "display"};
    const QColor colours[] = {QColor(31, 119, 180), QColor(255, 127, 14), QColor(44, 160, 44),
                              QColor(214, 39, 40),  QColor(148, 103, 189), QColor(140, 86, 75)};
    for (int i = 0; i < 6; ++i) {
      PlotLine line{telemetry::series::kLatencyStages[i], stage_names[i], colours[i]};
      line.fill_to_zero = i == 0;
      line.fill_to_previous = i > 0;
      p.lines.push_back(line);
    }
    plots.push_back(p);
  }
  plots.push_back(PlotSpec{"Head pose → robot latency", "XR sample → robot head loop [ms]", "",
                           {PlotLine{telemetry::series::kHeadLatency, "head pose → robot", QColor(31, 119, 180)}}});
  plots.push_back(PlotSpec{"Head motion (paper Fig. 6)", "velocity [cm/s]", "",
                           {PlotLine{telemetry::series::kVOp, "v_op (operator)", QColor(31, 119, 180)},
                            PlotLine{telemetry::series::kVRob, "v_rob (robot head)", QColor(214, 39, 40)}}});
  {
    PlotSpec p{"Eye ↔ camera deviation (paper Fig. 7)", "Δs [cm]", "v_op [cm/s]", {}};
    p.lines.push_back(PlotLine{telemetry::series::kDeltaS, "Δs (left eye ↔ left camera)", QColor(31, 119, 180)});
    PlotLine v{telemetry::series::kVOp, "v_op (operator)", QColor(214, 39, 40)};
    v.right_axis = true;
    p.lines.push_back(v);
    plots.push_back(p);
  }
  {
    PlotSpec p{"XR frames", "render time, both eyes [ms]", "missed display frames", {}};
    p.lines.push_back(PlotLine{telemetry::series::kXrFrameMs, "render time", QColor(44, 160, 44)});
    PlotLine missed{telemetry::series::kXrMissed, "missed frames", QColor(214, 39, 40)};
    missed.right_axis = true;
    missed.impulses = true;
    p.lines.push_back(missed);
    plots.push_back(p);
  }
  {
    // The operator's scene proxy (#35): what each eye's sphere has, and how sure each camera's depth is.
    PlotSpec p{"Scene depth", "scene radius [m]", "stereo tiles matched [%]", {}};
    p.lines.push_back(PlotLine{telemetry::series::kDepthRadiusLeftM, "radius, left eye", QColor(31, 119, 180)});
    p.lines.push_back(PlotLine{telemetry::series::kDepthRadiusRightM, "radius, right eye", QColor(255, 127, 14)});
    PlotLine matched_left{telemetry::series::kDepthMatchedLeftPct, "tiles matched, left camera", QColor(44, 160, 44)};
    matched_left.right_axis = true;
    p.lines.push_back(matched_left);
    PlotLine matched_right{telemetry::series::kDepthMatchedRightPct, "tiles matched, right camera", QColor(214, 39, 40)};
    matched_right.right_axis = true;
    p.lines.push_back(matched_right);
    plots.push_back(p);
  }
  // How old the depth the eyes use is, and what a sweep of a pair costs the operator's CPU: the
  // age grows when sweeps fall behind the images (pairs skipped), the sweep time says why.
  plots.push_back(PlotSpec{"Scene depth timing", "time [ms]", "",
                           {PlotLine{telemetry::series::kDepthAgeMs, "depth age (capture → in use)", QColor(148, 103, 189)},
                            PlotLine{telemetry::series::kDepthSweepMs, "sweep CPU time per pair", QColor(140, 86, 75)}}});
  return plots;
}

}  // namespace telesphere::console
