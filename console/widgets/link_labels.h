// SPDX-License-Identifier: MIT
/// @brief The link's enums as the console's panels name them (one wording everywhere).
#pragma once

#include <QString>

#include "console/supervision/visual_mode_label.h"
#include "robot/link/proto_enums.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console {

/// The mode in force as the panels name it (console/supervision/visual_mode_label.h); "?" for
/// one this console does not know.
inline QString visualModeLabel(link::proto::VisualMode mode) {
  const auto known = link::fromProto(mode);
  if (!known) return "?";
  const std::string_view label = supervision::visualModeLabel(*known);
  return QString::fromUtf8(label.data(), static_cast<qsizetype>(label.size()));
}

/// The scene proxy (#35) as the panels name it: "fixed sphere", "one radius from depth", "depth
/// grid"; `unspecified` where nobody chose one; "unknown (7)" for one this console lacks.
inline QString depthProxyLabel(link::proto::DepthProxyProto proxy, const QString& unspecified) {
  if (proxy == link::proto::DEPTH_PROXY_UNSPECIFIED) return unspecified;
  const auto known = link::fromProto(proxy);
  if (!known) return QString("unknown (%1)").arg(int(proxy));
  switch (*known) {
    case link::DepthProxy::kFixed: return "fixed sphere";
    case link::DepthProxy::kRadius: return "one radius from depth";
    case link::DepthProxy::kGrid: return "depth grid";
  }
  return "?";
}

/// What the frames carry (#34), as the panels name it: "MJPEG q90", "H.264 (libx264) · 20 Mbit/s",
/// "HEVC (opening) · 20 Mbit/s" before the first frame; "unknown (7)" for a codec this console lacks.
inline QString videoCodecLabel(const link::proto::RobotSettings& settings) {
  const auto codec = link::fromProto(settings.video_codec());
  if (!codec) return QString("unknown (%1)").arg(int(settings.video_codec()));
  if (*codec == link::VideoCodec::kMjpeg) return QString("MJPEG q%1").arg(settings.jpeg_quality());
  return QString("%1 (%2) · %3 Mbit/s")
      .arg(*codec == link::VideoCodec::kH264 ? "H.264" : "HEVC")
      .arg(settings.video_encoder().empty() ? QString("opening") : QString::fromStdString(settings.video_encoder()))
      .arg(settings.video_mbit());
}

inline QString nominalStepLabel(link::proto::NominalStep step) {
  switch (step) {
    case link::proto::NOMINAL_STEP_FOLLOWING: return "following the operator";
    case link::proto::NOMINAL_STEP_HOLDING: return "holding the nominal pose";
    case link::proto::NOMINAL_STEP_CAPTURED: return "nominal pose captured, to confirm";
    default: return "?";
  }
}

}  // namespace telesphere::console
