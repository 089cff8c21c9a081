// SPDX-License-Identifier: MIT
/// @brief Intrinsic calibration of one camera or of the stereo pair (DESIGN.md §6, paper §III-B):
///        the parameters of each camera (double sphere, EUCM, KB4 or pinhole-radtan) and
///        T_cam_l_cam_r, by Ceres over all views of a planar target.
///
/// Unknowns: per camera its parameters (kalibr/Basalt order), per view T_cam_l_board, and for a
/// stereo pair T_cam_l_cam_r. Residual per observed corner c of view v:
///   cam_l: f_l(T_cam_l_board(v)·p_board(c)) − px(c),
///   cam_r: f_r(T_cam_l_cam_r⁻¹·T_cam_l_board(v)·p_board(c)) − px(c),
/// under a Huber loss (δ = huber_px). A corner whose prediction does not project (during the
/// solve) contributes nothing instead of failing the step; parameters stay inside each model's
/// domain by bounds. Initialisation: focal length by a search over the views scored by
/// reprojection error, board poses from bearing vectors (calib/bearing_pose.h), so that views
/// near and beyond 90° off-axis contribute from the start; each camera is solved alone, then
/// both together with T_cam_l_cam_r averaged over the views both cameras see.
/// One concept: one Ceres problem (about 560 lines) — its parameter blocks, residuals, initial
/// guesses and the result's figures all follow the one layout of cameras and views above.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calib/calibration_failure.h"
#include "calib/pose_stddev.h"
#include "calib/system_calibration.h"
#include "calib/target_detection.h"

namespace telesphere::calib {

/// The views of one camera: views[v] holds the target's corners in view v (empty when the target
/// was not seen); for a stereo pair views[v] of both cameras are taken at the same time.
struct CameraViews {
  std::string label = "cam_l";  ///< "cam_l" or "cam_r"
  std::string model = "ds";     ///< "ds", "eucm", "kb4" or "pinhole"
  int width = 0;                ///< px
  int height = 0;               ///< px
  /// Start from these parameters instead of the automatic initialisation.
  std::optional<Eigen::VectorXd> initial_params;
  std::vector<TargetObservation> views;
};

struct IntrinsicOptions {
  double huber_px = 1.0;         ///< Huber loss threshold, px
  int max_iterations = 100;
  int min_corners_per_view = 12; ///< views with fewer corners are not used
  int min_views = 3;             ///< per camera
  double max_rms_px = 5.0;       ///< a final RMS above this means the solve diverged
  bool covariance = true;        ///< compute parameter standard deviations and separability
  /// Separability check (needs `covariance`): a multiple correlation of fx or fy with the
  /// model's distortion parameters above this means the views do not separate the focal length
  /// from the distortion (see CameraIntrinsicResult::degeneracy_warning).
  double max_focal_correlation = 0.999;
  int num_threads = 1;
  std::function<void(const std::string&)> progress;  ///< one line per step and iteration
};

struct ViewError {
  int view = 0;
  int corners = 0;     ///< corners that project with the final parameters
  double rms_px = 0;
};

/// One corner's final residual (for the coverage picture and the report).
struct CornerResidual {
  int view = 0;
  int corner_id = 0;
  Eigen::Vector2d px;        ///< observed
  Eigen::Vector2d error_px;  ///< predicted − observed
};

struct CameraIntrinsicResult {
  explicit CameraIntrinsicResult(CameraCalibration c) : calibration(std::move(c)) {}

  CameraCalibration calibration;
  double rms_px = 0;   ///< over all corners that project with the final parameters
  double mean_px = 0;  ///< mean |error|
  int corners = 0;
  int views_used = 0;
  std::vector<ViewError> per_view;
  std::vector<CornerResidual> residuals;
  /// Standard deviation of each parameter (kalibr order) from the covariance, scaled by the
  /// residual variance; empty when the covariance is unavailable (rank deficient).
  std::vector<double> param_stddev;
  /// Correlation matrix of the parameters (kalibr order) from the covariance; empty when the
  /// covariance was not computed or is unavailable.
  Eigen::MatrixXd param_correlation;
  /// Multiple correlation R of the worse of fx, fy with the model's distortion parameters
  /// (ds: xi, alpha; eucm: alpha, beta; kb4: k1..k4; pinhole: k1, k2, p1, p2), from
  /// param_correlation: R² = 1 − 1/(C⁻¹)₀₀ over the sub-matrix C of (focal, distortion). Near 1
  /// when the views cannot tell a longer focal length from more distortion (e.g. all views
  /// fronto-parallel at the image centre); NaN when the covariance is unavailable.
  double focal_distortion_correlation = NAN;
  /// Empty when the parameters are separable; otherwise a warning for the user naming the
  /// parameters that trade off and what views would separate them. Set when
  /// focal_distortion_correlation exceeds IntrinsicOptions::max_focal_correlation or the
  /// covariance is rank deficient.
  std::string degeneracy_warning;
};

struct IntrinsicResult {
  std::vector<CameraIntrinsicResult> cameras;
  std::optional<Eigen::Isometry3d> T_cam_l_cam_r;
  /// Standard deviations of T_cam_l_cam_r (translation in cam_l, rotation about cam_l's axes);
  /// not valid for one camera, without IntrinsicOptions::covariance or when rank deficient.
  PoseStddev T_cam_l_cam_r_stddev;
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_l_board;  ///< per view; nothing if unused
  double initial_cost = 0;  ///< of the final joint problem, ½Σρ(|r|²)
  double final_cost = 0;
  int iterations = 0;
  double solve_seconds = 0;

  /// True when a camera carries a degeneracy warning.
  bool degenerate() const;

  /// The cameras (and T_cam_l_cam_r) as a system calibration.
  SystemCalibration toSystemCalibration() const;
};

/// Calibrates one camera (cameras.size() == 1) or a stereo pair (cameras[0] = cam_l,
/// cameras[1] = cam_r, views aligned in time).
/// `target` gives the corners' board positions (corner ids of calib/aprilgrid.h).
SolveResult<IntrinsicResult> calibrateIntrinsics(const AprilGrid& target,
                                                 const std::vector<CameraViews>& cameras,
                                                 const IntrinsicOptions& options = {});

/// Default parameters of `model` with focal length `f` px and the principal point at the image
/// centre: ds xi 0 alpha 0.5 and eucm alpha 0.5 beta 1 (both stereographic), kb4 equidistant,
/// pinhole undistorted.
Eigen::VectorXd defaultParams(const std::string& model, double f, int width, int height);

}  // namespace telesphere::calib
