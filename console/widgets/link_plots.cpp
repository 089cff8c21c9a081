// SPDX-License-Identifier: MIT
/// @brief linkPlots: the four plot specifications of the link panel.
#include "console/widgets/link_plots.h"

#include "console/telemetry/media_link_series.h"
#include "console/telemetry/telemetry_model.h"

namespace telesphere::console {

std::vector<PlotSpec> linkPlots() {
  namespace s = telemetry::series;
  const QColor blue(31, 119, 180), orange(255, 127, 14), green(44, 160, 44), red(214, 39, 40),
      purple(148, 103, 189), brown(140, 86, 75);
  std::vector<PlotSpec> plots;
  plots.push_back(PlotSpec{"Media path rate", "rate [Mbit/s]", "",
                           {PlotLine{s::kLinkDeliveredMbit, "delivered (estimate)", green},
                            PlotLine{s::kLinkTargetMbit, "target", blue},
                            PlotLine{s::kLinkCapMbit, "supervisor's cap", red}}});
  plots.push_back(PlotSpec{"Delay", "delay [ms]", "",
                           {PlotLine{s::kLatencyStages[5], "frame age (capture → displayed)", brown},
                            PlotLine{s::kLinkRttMs, "round trip", blue},
                            PlotLine{s::kLinkQueueMs, "queuing", orange}}});
  {
    PlotSpec p{"Loss and repair", "datagram loss before repair [%]", "per second [1/s]", {}};
    p.lines.push_back(PlotLine{s::kLinkLossPct, "loss", red});
    PlotLine repaired{s::kLinkRepairedPerS, "chunks repaired (FEC)", green};
    repaired.right_axis = true;
    p.lines.push_back(repaired);
    PlotLine concealed{s::kLinkConcealedPerS, "bands concealed", orange};
    concealed.right_axis = true;
    p.lines.push_back(concealed);
    PlotLine lost{s::kLinkLostFramesPerS, "frames lost", purple};
    lost.right_axis = true;
    lost.impulses = true;
    p.lines.push_back(lost);
    plots.push_back(p);
  }
  {
    PlotSpec p{"Stream settings", "frame rate [Hz] · JPEG quality", "scale per axis [%]", {}};
    p.lines.push_back(PlotLine{s::kLinkFps, "frame rate", blue});
    p.lines.push_back(PlotLine{s::kLinkQuality, "JPEG quality", orange});
    PlotLine scale{s::kLinkScalePct, "scale", green};
    scale.right_axis = true;
    p.lines.push_back(scale);
    plots.push_back(p);
  }
  return plots;
}

}  // namespace telesphere::console
