// SPDX-License-Identifier: MIT
/// @brief The camera models compared on the same samples (issue #15: "model only what the scene
///        requires"): each of ds, eucm, kb4 and pinhole-radtan solved on the kept views, its RMS,
///        parameter count and solve time, and the simplest model whose RMS is within the user's
///        tolerance preselected (fewest parameters, then lowest RMS). A model that cannot
///        represent the views (pinhole beyond 90° off axis) says why.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "calib/aprilgrid.h"
#include "console/calibration/intrinsics_collector.h"

namespace telesphere::console::calibration {

struct ModelFit {
  std::string model;
  bool ok = false;
  std::string message;  ///< why not, when !ok
  double rms_px = 0;    ///< the worse of the two cameras
  int parameters = 0;   ///< per camera
  int views_used = 0;   ///< of cam_l
  double solve_s = 0;
};

struct ModelComparison {
  std::vector<ModelFit> fits;
  std::optional<std::string> preselected;  ///< nothing when no model is within the tolerance
  double tolerance_px = 0;
};

/// Solves every model in `models` on the collector's samples (no covariance).
ModelComparison compareModels(const IntrinsicsCollector& collector, const calib::AprilGrid& grid, double tolerance_px,
                              const std::vector<std::string>& models = {"ds", "eucm", "kb4", "pinhole"});

}  // namespace telesphere::console::calibration
