// SPDX-License-Identifier: MIT
/// @brief Lenses the camera-model tests run on: a typical lens per model on a 3840×2160 sensor
///        (the >180° fisheyes of the paper for ds, eucm and kb4) and seeded random parameters
///        spanning each model's whole domain, edges included.
#pragma once

#include <Eigen/Core>
#include <random>
#include <vector>

#include "calib/double_sphere_camera.h"
#include "calib/extended_unified_camera.h"
#include "calib/kannala_brandt_camera.h"
#include "calib/pinhole_radtan_camera.h"
#include "calib/synthetic/typical_lenses.h"

namespace telesphere::test {

inline constexpr int kWidth = calib::synthetic::kTypicalSensorWidthPx;
inline constexpr int kHeight = calib::synthetic::kTypicalSensorHeightPx;

template <template <typename> class Model>
struct Lens;

template <>
struct Lens<calib::DoubleSphereCamera> {
  static Eigen::Matrix<double, 6, 1> typical() {
    return calib::synthetic::TypicalLens<calib::DoubleSphereCamera>::parameters();
  }
  static bool widerThan180() { return true; }
  static Eigen::Matrix<double, 6, 1> random(std::mt19937& rng) {
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const double f = 50.0 + 3000.0 * u01(rng);
    // Edges of the domain on purpose: alpha exactly 0, 0.5, 1 and xi near 0 and large.
    const double alphas[] = {0.0, 0.5, 1.0, u01(rng), u01(rng), u01(rng)};
    const double xis[] = {0.0, 1e-9, -0.9, 5.0, 1e3, -0.5 + 2.5 * u01(rng), -0.5 + 2.5 * u01(rng)};
    const double alpha = alphas[rng() % 6];
    const double xi = xis[rng() % 7];
    return (Eigen::Matrix<double, 6, 1>() << f, f * (0.9 + 0.2 * u01(rng)), kWidth * u01(rng),
            kHeight * u01(rng), xi, alpha)
        .finished();
  }
};

template <>
struct Lens<calib::ExtendedUnifiedCamera> {
  static Eigen::Matrix<double, 6, 1> typical() {
    return calib::synthetic::TypicalLens<calib::ExtendedUnifiedCamera>::parameters();
  }
  static bool widerThan180() { return true; }
  static Eigen::Matrix<double, 6, 1> random(std::mt19937& rng) {
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const double f = 50.0 + 3000.0 * u01(rng);
    const double alphas[] = {0.0, 0.5, 1.0, u01(rng), u01(rng)};
    const double betas[] = {1.0, 1e-3, 50.0, 0.2 + 3.0 * u01(rng), 0.2 + 3.0 * u01(rng)};
    return (Eigen::Matrix<double, 6, 1>() << f, f * (0.9 + 0.2 * u01(rng)), kWidth * u01(rng),
            kHeight * u01(rng), alphas[rng() % 5], betas[rng() % 5])
        .finished();
  }
};

template <>
struct Lens<calib::KannalaBrandtCamera> {
  static Eigen::Matrix<double, 8, 1> typical() {
    return calib::synthetic::TypicalLens<calib::KannalaBrandtCamera>::parameters();
  }
  static bool widerThan180() { return true; }
  static Eigen::Matrix<double, 8, 1> random(std::mt19937& rng) {
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::uniform_real_distribution<double> k(-0.05, 0.05);
    const double f = 50.0 + 3000.0 * u01(rng);
    return (Eigen::Matrix<double, 8, 1>() << f, f * (0.9 + 0.2 * u01(rng)), kWidth * u01(rng),
            kHeight * u01(rng), 4 * k(rng), k(rng), k(rng) / 4, k(rng) / 16)
        .finished();
  }
};

template <>
struct Lens<calib::PinholeRadtanCamera> {
  static Eigen::Matrix<double, 8, 1> typical() {
    return calib::synthetic::TypicalLens<calib::PinholeRadtanCamera>::parameters();
  }
  static bool widerThan180() { return false; }
  static Eigen::Matrix<double, 8, 1> random(std::mt19937& rng) {
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::uniform_real_distribution<double> k(-0.3, 0.3);
    const double f = 300.0 + 3000.0 * u01(rng);
    return (Eigen::Matrix<double, 8, 1>() << f, f * (0.9 + 0.2 * u01(rng)), kWidth * u01(rng),
            kHeight * u01(rng), k(rng), k(rng) / 3, k(rng) / 100, k(rng) / 100)
        .finished();
  }
};

/// Unit directions spread evenly over the whole sphere (Fibonacci lattice), poles included.
inline std::vector<Eigen::Vector3d> sphereDirections(int n) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(n + 2);
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(1.0 - z * z);
    out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  out.emplace_back(0, 0, 1);
  out.emplace_back(0, 0, -1);
  return out;
}

/// The direction at angle theta from +z, rotated by phi about z.
inline Eigen::Vector3d directionAt(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

}  // namespace telesphere::test
