// SPDX-License-Identifier: MIT
/// @brief The intrinsic calibration's done rule (see intrinsics_done_rule.h).
#include "console/calibration/intrinsics_done_rule.h"

#include <cmath>
#include <cstdio>

namespace telesphere::console::calibration {
namespace {

std::string format(const char* fmt, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

}  // namespace

std::string IntrinsicsDoneRule::describe(double polar_bin_deg) const {
  char buf[600];
  std::snprintf(buf, sizeof buf,
                "%d views · a corner in every %.0f° polar-angle bin out to the last that holds ≥ %.1f %% of the image and "
                "where the board's tags span ≥ %.0f px a cell, in both cameras · σ(fx, fy) ≤ %.2f %% of f, σ(cx, cy) ≤ "
                "%.2f %% of the image width · RMS ≤ %.2f px · no degeneracy warning",
                min_views, polar_bin_deg, 100.0 * min_bin_image_share, min_px_per_tag_cell, 100.0 * max_focal_std_rel,
                100.0 * max_principal_std_rel, max_rms_px);
  return buf;
}

std::string DoneCheck::describe() const {
  if (unmet.empty()) return "done";
  std::string s;
  for (const std::string& u : unmet) s += (s.empty() ? "" : "; ") + u;
  return s;
}

namespace {

bool binHoldsShare(const calib::ViewCoverage& coverage, const IntrinsicsDoneRule& rule, int bin) {
  return coverage.imageShare(bin) >= rule.min_bin_image_share;
}

bool tagsReadable(const calib::ViewCoverage& coverage, const IntrinsicsDoneRule& rule, int bin) {
  // No tag angle, or no scale known (the bin's middle lies outside the image): the share decides.
  if (rule.tag_angle_deg <= 0 || coverage.radialPxPerDeg(bin) <= 0) return true;
  return coverage.radialPxPerDeg(bin) * rule.tag_angle_deg >= rule.tag_cells * rule.min_px_per_tag_cell;
}

}  // namespace

std::vector<int> requiredPolarBins(const calib::ViewCoverage& coverage, const IntrinsicsDoneRule& rule) {
  // Every bin from the centre out to the last one that holds the share and whose tags can be
  // read (the centre bin is a small disc: it is required although it holds little of the image).
  int last = -1;
  for (int b = 0; b < coverage.polarBins(); ++b)
    if (binHoldsShare(coverage, rule, b) && tagsReadable(coverage, rule, b)) last = b;
  std::vector<int> bins;
  for (int b = 0; b <= last; ++b) bins.push_back(b);
  return bins;
}

std::vector<int> unreadablePolarBins(const calib::ViewCoverage& coverage, const IntrinsicsDoneRule& rule) {
  const std::vector<int> required = requiredPolarBins(coverage, rule);
  std::vector<int> bins;
  for (int b = required.empty() ? 0 : required.back() + 1; b < coverage.polarBins(); ++b)
    if (binHoldsShare(coverage, rule, b) && !tagsReadable(coverage, rule, b)) bins.push_back(b);
  return bins;
}

std::vector<int> missingPolarBins(const calib::ViewCoverage& coverage, const IntrinsicsDoneRule& rule) {
  std::vector<int> missing;
  for (int b : requiredPolarBins(coverage, rule))
    if (coverage.polarCount(b) == 0) missing.push_back(b);
  return missing;
}

DoneCheck checkCollection(int views, const std::vector<const calib::ViewCoverage*>& coverage,
                          const IntrinsicsDoneRule& rule) {
  DoneCheck check;
  if (views < rule.min_views) check.unmet.push_back(format("%.0f of %.0f views", views, rule.min_views));
  for (std::size_t c = 0; c < coverage.size(); ++c) {
    const calib::ViewCoverage& cov = *coverage[c];
    std::string missing;
    for (int b : missingPolarBins(cov, rule))
      missing += (missing.empty() ? "" : ", ") + format("%.0f–%.0f°", b * cov.polarBinDeg(), (b + 1) * cov.polarBinDeg());
    if (!missing.empty()) {
      check.unmet.push_back(std::string(c == 0 ? "cam_l" : "cam_r") + ": no corner yet at polar angles " + missing);
    }
  }
  return check;
}

DoneCheck checkSolve(const calib::IntrinsicResult& result, const IntrinsicsDoneRule& rule) {
  DoneCheck check;
  for (const calib::CameraIntrinsicResult& cam : result.cameras) {
    const std::string& label = cam.calibration.label;
    if (!cam.degeneracy_warning.empty()) {
      const bool labelled = cam.degeneracy_warning.rfind(label, 0) == 0;  // the solver names the camera itself
      check.unmet.push_back(labelled ? cam.degeneracy_warning : label + ": " + cam.degeneracy_warning);
    }
    if (!(cam.rms_px <= rule.max_rms_px)) {
      check.unmet.push_back(label + format(": RMS %.3f px (%.2f allowed)", cam.rms_px, rule.max_rms_px));
    }
    if (cam.param_stddev.size() < 4) {
      check.unmet.push_back(label + ": no standard deviations (the covariance is rank deficient)");
      continue;
    }
    const char* names[4] = {"fx", "fy", "cx", "cy"};
    const Eigen::VectorXd p = cam.calibration.camera.params();
    for (int i = 0; i < 4; ++i) {
      const double bound = i < 2 ? rule.max_focal_std_rel * p[i] : rule.max_principal_std_rel * cam.calibration.width;
      if (!(cam.param_stddev[std::size_t(i)] <= bound)) {
        check.unmet.push_back(label + ": σ(" + names[i] + ") " +
                              format("%.3f px (%.2f allowed)", cam.param_stddev[std::size_t(i)], bound));
      }
    }
  }
  return check;
}

}  // namespace telesphere::console::calibration
