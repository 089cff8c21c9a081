// SPDX-License-Identifier: MIT
/// @brief When the intrinsic (and stereo) calibration is done, stated with numbers (issue #15):
///        enough views; in each camera every polar-angle bin reached out to a margin short of
///        the widest angle the image sees (the rim is where a fisheye model is least
///        constrained); and after the solve, the focal lengths' and principal point's standard
///        deviations below a bound, the RMS below a bound and no degeneracy warning. Each check
///        that fails says what it measured and what it needs; the wizard page shows describe().
#pragma once

#include <string>
#include <vector>

#include "calib/intrinsic_calibration.h"
#include "calib/view_coverage.h"

namespace telesphere::console::calibration {

struct IntrinsicsDoneRule {
  int min_views = 20;                 ///< stereo samples kept
  /// Polar bins beyond the last one that holds this share of the image's pixels are optional: the widest
  /// angles of a lens beyond 180° on a 16:9 sensor lie only in the image's extreme corners, where
  /// a planar board is cut by the border and squeezed beyond what the detector reads (the
  /// simulated 4K lens: 110–120° is 1.5 % of the image, its corners; no corner was detected in
  /// stills with the board centred there).
  double min_bin_image_share = 0.02;
  /// Polar bins where the board's tags are too small to read are optional too: the rim is
  /// squeezed radially, and a tag's cells (10 across a kalibr Aprilgrid tag: 6 data, 2 border on
  /// each side) each need this many pixels in the bin's middle (2: the sampling limit; the
  /// simulated cam_l at 1280×720 spans 16.7 px a 4.2° tag at 105°, and the stills with the board
  /// near the image's corners read 0–8 of the ~20 tags in view).
  double min_px_per_tag_cell = 2.0;
  int tag_cells = 10;
  /// A tag's angular size from the camera (its size over the board's distance, deg); the
  /// procedure sets it once it has found the board. 0: no readability limit.
  double tag_angle_deg = 0.0;
  double max_focal_std_rel = 0.002;      ///< σ(fx)/fx, σ(fy)/fy
  double max_principal_std_rel = 0.001;  ///< σ(cx), σ(cy) over the image width
  double max_rms_px = 1.0;

  /// "20 views · every 10° polar bin holding ≥ 1 % of the image, both cameras · σ(f) ≤ 0.2 % of
  /// f, σ(c) ≤ 0.1 % of the width · RMS ≤ 1 px · no degeneracy".
  std::string describe(double polar_bin_deg) const;
};

struct DoneCheck {
  std::vector<std::string> unmet;  ///< empty: done
  bool done() const { return unmet.empty(); }
  std::string describe() const;  ///< "done" or the unmet checks joined by "; "
};

/// The polar bins a camera must reach under `rule`: from the centre out to the last bin that
/// holds rule.min_bin_image_share of the image and where a tag rule.tag_angle_deg across spans
/// rule.tag_cells × rule.min_px_per_tag_cell pixels radially (coverage.radialPxPerDeg).
std::vector<int> requiredPolarBins(const calib::ViewCoverage& coverage, const IntrinsicsDoneRule& rule);

/// The required polar bins (requiredPolarBins) that hold no corner yet.
std::vector<int> missingPolarBins(const calib::ViewCoverage& coverage, const IntrinsicsDoneRule& rule);

/// The bins beyond the required ones that hold rule.min_bin_image_share of the image but where
/// the tags are too small to read (the supervisor can bring the board closer for them).
std::vector<int> unreadablePolarBins(const calib::ViewCoverage& coverage, const IntrinsicsDoneRule& rule);

/// Before the solve: views and coverage (one ViewCoverage per camera, labelled "cam_l", "cam_r").
DoneCheck checkCollection(int views, const std::vector<const calib::ViewCoverage*>& coverage,
                          const IntrinsicsDoneRule& rule);

/// After the solve: standard deviations, RMS and degeneracy of every camera.
DoneCheck checkSolve(const calib::IntrinsicResult& result, const IntrinsicsDoneRule& rule);

}  // namespace telesphere::console::calibration
