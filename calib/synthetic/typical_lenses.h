// SPDX-License-Identifier: MIT
/// @brief A typical lens per camera model on a 3840×2160 sensor, the lenses the benchmarks and the
///        camera-model tests measure: the paper's >180° fisheyes for ds, eucm and kb4, and a
///        ~94° pinhole with radial-tangential distortion.
#pragma once

#include <Eigen/Core>

#include "calib/double_sphere_camera.h"
#include "calib/extended_unified_camera.h"
#include "calib/kannala_brandt_camera.h"
#include "calib/pinhole_radtan_camera.h"

namespace telesphere::calib::synthetic {

inline constexpr int kTypicalSensorWidthPx = 3840;
inline constexpr int kTypicalSensorHeightPx = 2160;

template <template <typename> class Model>
struct TypicalLens;

template <>
struct TypicalLens<DoubleSphereCamera> {
  /// fx, fy, cx, cy, xi, alpha: about 196° across the image width.
  static Eigen::Matrix<double, 6, 1> parameters() {
    return (Eigen::Matrix<double, 6, 1>() << 930, 931, 1919.5, 1079.5, -0.18, 0.59).finished();
  }
};

template <>
struct TypicalLens<ExtendedUnifiedCamera> {
  /// fx, fy, cx, cy, alpha, beta.
  static Eigen::Matrix<double, 6, 1> parameters() {
    return (Eigen::Matrix<double, 6, 1>() << 1100, 1101, 1919.5, 1079.5, 0.62, 1.05).finished();
  }
};

template <>
struct TypicalLens<KannalaBrandtCamera> {
  /// fx, fy, cx, cy, k1..k4.
  static Eigen::Matrix<double, 8, 1> parameters() {
    return (Eigen::Matrix<double, 8, 1>() << 1080, 1081, 1919.5, 1079.5, 0.02, -0.005, 0.001, -0.0001)
        .finished();
  }
};

template <>
struct TypicalLens<PinholeRadtanCamera> {
  /// fx, fy, cx, cy, k1, k2, p1, p2.
  static Eigen::Matrix<double, 8, 1> parameters() {
    return (Eigen::Matrix<double, 8, 1>() << 1800, 1801, 1919.5, 1079.5, -0.2, 0.05, 1e-4, -2e-4).finished();
  }
};

}  // namespace telesphere::calib::synthetic
