// SPDX-License-Identifier: MIT
/// @brief compareModels (see model_comparison.h).
#include "console/calibration/model_comparison.h"

#include <algorithm>
#include <chrono>

#include "calib/generic_camera.h"
#include "calib/intrinsic_calibration.h"

namespace telesphere::console::calibration {

ModelComparison compareModels(const IntrinsicsCollector& collector, const calib::AprilGrid& grid, double tolerance_px,
                              const std::vector<std::string>& models) {
  ModelComparison comparison;
  comparison.tolerance_px = tolerance_px;
  for (const std::string& model : models) {
    ModelFit fit;
    fit.model = model;
    fit.parameters = int(calib::GenericCamera::paramNames(model).size());
    calib::IntrinsicOptions options;
    options.covariance = false;
    const auto t0 = std::chrono::steady_clock::now();
    auto solved = calib::calibrateIntrinsics(grid, collector.cameraViews(model), options);
    fit.solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (solved) {
      fit.ok = true;
      for (const calib::CameraIntrinsicResult& cam : solved->cameras) fit.rms_px = std::max(fit.rms_px, cam.rms_px);
      fit.views_used = solved->cameras[0].views_used;
      // Views the model could not use count against it: a model that drops the rim is not "as good".
      const int offered = int(std::count_if(collector.samples().begin(), collector.samples().end(),
                                            [](const StereoSample& s) { return !s.views[0].empty(); }));
      if (fit.views_used < offered) {
        fit.message = std::to_string(offered - fit.views_used) + " of " + std::to_string(offered) +
                      " views could not be used";
      }
    } else {
      fit.message = solved.failure().message;
    }
    comparison.fits.push_back(fit);
  }
  const ModelFit* best = nullptr;
  for (const ModelFit& fit : comparison.fits) {
    if (!fit.ok || !fit.message.empty() || fit.rms_px > tolerance_px) continue;
    if (best == nullptr || fit.parameters < best->parameters ||
        (fit.parameters == best->parameters && fit.rms_px < best->rms_px)) {
      best = &fit;
    }
  }
  if (best != nullptr) comparison.preselected = best->model;
  return comparison;
}

}  // namespace telesphere::console::calibration
