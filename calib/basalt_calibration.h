// SPDX-License-Identifier: MIT
/// @brief Import and export of Basalt's calibration JSON (cereal layout, top-level "value0").
///
/// Basalt stores per camera `intrinsics[i] = {camera_type, intrinsics: {named params}}`,
/// `resolution[i] = [w, h]` and `T_imu_cam[i] = {px, py, pz, qx, qy, qz, qw}`. Camera types:
/// "ds" {fx fy cx cy xi alpha}, "eucm" {fx fy cx cy alpha beta}, "kb4" {fx fy cx cy k1..k4},
/// "pinhole" {fx fy cx cy} (no distortion) and "pinhole-radtan8" {fx fy cx cy k1 k2 p1 p2 k3 k4
/// k5 k6 rpmax}, the last read into our "pinhole" when k3..k6 are 0 (else an error: we do not
/// model the rational terms) — so all four of our models go across losslessly.
/// We have no IMU: import keeps only the cameras' relative pose, T_cam_l_cam_r =
/// T_imu_cam[0]⁻¹·T_imu_cam[1]; export writes T_imu_cam[0] = identity (the IMU frame placed at
/// cam_l), T_imu_cam[1] = T_cam_l_cam_r, and the IMU fields Basalt's reader expects, zeroed.
#pragma once

#include <string>

#include "calib/file_error.h"
#include "calib/system_calibration.h"

namespace telesphere::calib {

FileResult<SystemCalibration> parseBasaltCalibration(const std::string& text, const std::string& path);
std::string toBasaltCalibration(const SystemCalibration& calibration);

}  // namespace telesphere::calib
