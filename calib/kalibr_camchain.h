// SPDX-License-Identifier: MIT
/// @brief Import and export of kalibr's camchain.yaml, so users keep their existing tools.
///
/// kalibr (ethz-asl/kalibr, "Supported models" in its wiki) writes per camera `camN`:
///   camera_model: ds | eucm | pinhole   (also omni, which we do not model)
///   intrinsics:   ds [xi, alpha, fu, fv, pu, pv]; eucm [alpha, beta, fu, fv, pu, pv];
///                 pinhole [fu, fv, pu, pv]
///   distortion_model: none | radtan [k1, k2, r1, r2] | equidistant [k1, k2, k3, k4]
///   resolution: [w, h]
///   T_cn_cnm1: 4×4, maps points from cam(N−1) into camN (cam1 only for us: T_cam_r_cam_l).
/// Mapping: ds → "ds", eucm → "eucm", pinhole+none/radtan → "pinhole", pinhole+equidistant →
/// "kb4". Parameters go across unchanged (17 significant digits), so ours → kalibr → ours is
/// lossless for these models; transforms are exact to rounding (1e-15).
#pragma once

#include <string>

#include "calib/file_error.h"
#include "calib/system_calibration.h"

namespace telesphere::calib {

/// Reads cam0 (→ cam_l) and cam1 (→ cam_r, with T_cam_l_cam_r = T_cn_cnm1⁻¹). Other fields of the
/// file (rostopic, cam_overlaps, T_cam_imu, timeshift_cam_imu) are not part of our calibration
/// and are ignored; more than two cameras is an error.
FileResult<SystemCalibration> parseKalibrCamchain(const std::string& text, const std::string& path);

/// A camchain.yaml with cam0 (and cam1). Hand-eye extrinsics have no place in kalibr's format
/// and are left out.
std::string toKalibrCamchain(const SystemCalibration& calibration);

}  // namespace telesphere::calib
