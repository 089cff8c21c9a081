// SPDX-License-Identifier: MIT
/// @brief The generic checks every camera model must pass, written once and instantiated per model
///        and scalar (STYLE.md §17): round trips over the whole image and the whole sphere,
///        validity against maxAngle(), Jacobians against central differences, float against
///        double, bad inputs, seeded random parameters.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "tests/calib/camera_model_fixtures.h"
#include "tests/support/jacobian_check.h"

namespace telesphere::test {
namespace {

using calib::DoubleSphereCamera;
using calib::ExtendedUnifiedCamera;
using calib::KannalaBrandtCamera;
using calib::PinholeRadtanCamera;

template <template <typename> class M, typename S>
struct Case {
  using Scalar = S;
  using Camera = M<S>;
  using DoubleCamera = M<double>;
  using Fixture = Lens<M>;
};

/// Round-trip tolerances per scalar: pixels, and radians on the sphere.
template <typename S>
struct Tol;
template <>
struct Tol<double> {
  static constexpr double px = 1e-6;
  static constexpr double rad = 1e-9;
  static constexpr double angle_margin = 1e-9;
  static constexpr double rim = 0.0;
};
template <>
struct Tol<float> {
  static constexpr double px = 0.02;
  static constexpr double rad = 2e-4;
  static constexpr double angle_margin = 2e-3;
  // Within 0.05 rad of maxAngle the ray→pixel→ray round trip is ill-conditioned (the image
  // radius flattens out), so float is held to the round-trip bound only inside it.
  static constexpr double rim = 0.05;
};

template <typename C>
class CameraModelTest : public ::testing::Test {};
using AllCases =
    ::testing::Types<Case<DoubleSphereCamera, double>, Case<DoubleSphereCamera, float>,
                     Case<ExtendedUnifiedCamera, double>, Case<ExtendedUnifiedCamera, float>,
                     Case<KannalaBrandtCamera, double>, Case<KannalaBrandtCamera, float>,
                     Case<PinholeRadtanCamera, double>, Case<PinholeRadtanCamera, float>>;
TYPED_TEST_SUITE(CameraModelTest, AllCases);

template <typename C>
typename C::Camera typicalCamera() {
  return typename C::Camera(C::Fixture::typical().template cast<typename C::Scalar>());
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

TYPED_TEST(CameraModelTest, PixelRoundTripOverWholeImage) {
  using S = typename TypeParam::Scalar;
  using Vec2 = Eigen::Matrix<S, 2, 1>;
  using Vec3 = Eigen::Matrix<S, 3, 1>;
  const auto cam = typicalCamera<TypeParam>();
  int valid = 0, total = 0;
  double max_err = 0.0, max_angle = 0.0;
  // Every 8th pixel plus the outermost pixel centres and the outer edges of the image.
  std::vector<double> us, vs;
  for (double u = -0.5; u < kWidth; u += 8) us.push_back(u);
  for (double v = -0.5; v < kHeight; v += 8) vs.push_back(v);
  us.insert(us.end(), {0.0, kWidth - 1.0, kWidth - 0.5});
  vs.insert(vs.end(), {0.0, kHeight - 1.0, kHeight - 0.5});
  for (double v : vs) {
    for (double u : us) {
      ++total;
      const Vec2 px{S(u), S(v)};
      Vec3 d;
      if (!cam.unproject(px, d)) {
        EXPECT_TRUE(d.isZero()) << "invalid unprojection must zero its output";
        continue;
      }
      ++valid;
      ASSERT_NEAR(static_cast<double>(d.norm()), 1.0, 100 * Tol<S>::rad) << "at " << u << ", " << v;
      Vec2 back;
      ASSERT_TRUE(cam.project(d, back)) << "unprojected ray does not project back at " << u << ", " << v;
      max_err = std::max(max_err, static_cast<double>((back - px).norm()));
      max_angle = std::max(max_angle, std::acos(std::clamp(static_cast<double>(d[2]), -1.0, 1.0)));
    }
  }
  EXPECT_LE(max_err, Tol<S>::px);
  EXPECT_GT(valid, total / 2);
  if (TypeParam::Fixture::widerThan180()) {
    EXPECT_GT(max_angle, M_PI / 2 + 0.1) << "the typical lens sees beyond 180°";
  }
  std::printf("max pixel round-trip error %.3g px\n", max_err);
}

TYPED_TEST(CameraModelTest, RayRoundTripOverWholeSphere) {
  using S = typename TypeParam::Scalar;
  using Vec2 = Eigen::Matrix<S, 2, 1>;
  using Vec3 = Eigen::Matrix<S, 3, 1>;
  const auto cam = typicalCamera<TypeParam>();
  const double max_angle = static_cast<double>(cam.maxAngle());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> log_scale(-3, 3);
  int valid = 0;
  for (const Eigen::Vector3d& dir : sphereDirections(20000)) {
    const double theta = std::acos(dir.z());
    const Vec3 p = (dir * std::pow(10.0, log_scale(rng))).cast<S>();
    Vec2 px;
    const bool ok = cam.project(p, px);
    if (theta < max_angle - Tol<S>::angle_margin) {
      EXPECT_TRUE(ok) << "θ = " << theta << " below maxAngle " << max_angle << " must project";
    }
    if (theta > max_angle + Tol<S>::angle_margin) {
      EXPECT_FALSE(ok) << "θ = " << theta << " above maxAngle " << max_angle << " must not project";
    }
    if (!ok) {
      EXPECT_TRUE(px.isZero());
      continue;
    }
    ++valid;
    if (theta > max_angle - Tol<S>::rim) continue;
    Vec3 d;
    ASSERT_TRUE(cam.unproject(px, d)) << "projected pixel does not unproject, θ = " << theta;
    EXPECT_LE(angleBetween(d.template cast<double>(), dir), Tol<S>::rad) << "θ = " << theta;
  }
  EXPECT_GT(valid, 1000);
}

TYPED_TEST(CameraModelTest, BadInputsGiveInvalidNeverNaN) {
  using S = typename TypeParam::Scalar;
  using Vec2 = Eigen::Matrix<S, 2, 1>;
  using Vec3 = Eigen::Matrix<S, 3, 1>;
  const auto cam = typicalCamera<TypeParam>();
  const S nan = std::numeric_limits<S>::quiet_NaN();
  const S inf = std::numeric_limits<S>::infinity();
  const S tiny = std::numeric_limits<S>::denorm_min();
  const S huge = std::numeric_limits<S>::max();
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(nan, 0, 1), Vec3(0, nan, 1), Vec3(0, 0, nan),
                        Vec3(inf, 0, 1), Vec3(0, -inf, 1), Vec3(0, 0, inf), Vec3(0, 0, -1),
                        Vec3(0, 0, -tiny), Vec3(0, 0, -huge)}) {
    Vec2 px(S(7), S(7));
    typename TypeParam::Camera::Mat2x3 J_p;
    typename TypeParam::Camera::Mat2xP J_params;
    EXPECT_FALSE(cam.project(p, px, &J_p, &J_params)) << "p = " << p.transpose();
    EXPECT_TRUE(px.isZero() && J_p.isZero() && J_params.isZero()) << "p = " << p.transpose();
  }
  // Extreme but valid points: a direction is a direction at any scale.
  Vec2 ref, px;
  ASSERT_TRUE(cam.project(Vec3(S(0.1), S(-0.2), S(1)), ref));
  for (const S scale : {tiny, S(1e-30), S(1e30), huge / S(2)}) {
    const Vec3 p = Vec3(S(0.1), S(-0.2), S(1)) * scale;
    if (!(p.array().abs() > S(0)).all() || !p.allFinite()) continue;  // the scale underflowed
    ASSERT_TRUE(cam.project(p, px)) << "scale " << scale;
    EXPECT_LE(static_cast<double>((px - ref).norm()), Tol<S>::px) << "scale " << scale;
  }
  for (const Vec2& bad : {Vec2(nan, 0), Vec2(0, inf), Vec2(-inf, -inf)}) {
    Vec3 d(S(1), S(1), S(1));
    EXPECT_FALSE(cam.unproject(bad, d));
    EXPECT_TRUE(d.isZero());
  }
  Vec3 d;
  for (const Vec2& far : {Vec2(S(1e30), S(0)), Vec2(S(-1e7), S(3e7))}) {
    if (cam.unproject(far, d)) {
      EXPECT_TRUE(d.allFinite());
    } else {
      EXPECT_TRUE(d.isZero());
    }
  }
}

TYPED_TEST(CameraModelTest, FloatAgreesWithDouble) {
  using S = typename TypeParam::Scalar;
  const typename TypeParam::DoubleCamera reference(TypeParam::Fixture::typical());
  const auto cam = reference.template cast<S>();
  double max_err = 0.0;
  for (const Eigen::Vector3d& dir : sphereDirections(20000)) {
    Eigen::Vector2d ref;
    Eigen::Matrix<S, 2, 1> px;
    if (!reference.project(dir, ref)) continue;
    if (std::acos(dir.z()) > reference.maxAngle() - 1e-3) continue;  // at the rim float may differ
    if (ref.x() < 0 || ref.y() < 0 || ref.x() > kWidth || ref.y() > kHeight) continue;
    ASSERT_TRUE(cam.project(dir.cast<S>(), px));
    max_err = std::max(max_err, (px.template cast<double>() - ref).norm());
  }
  // float has 24 bits: 2.4e-4 px of resolution at 4K coordinates.
  const double bound = std::is_same_v<S, float> ? 5e-3 : 1e-9;
  EXPECT_LE(max_err, bound);
}

// ---- double-only checks: Jacobians and seeded random parameters ----

template <typename C>
class CameraModelDoubleTest : public ::testing::Test {};
using DoubleCases =
    ::testing::Types<Case<DoubleSphereCamera, double>, Case<ExtendedUnifiedCamera, double>,
                     Case<KannalaBrandtCamera, double>, Case<PinholeRadtanCamera, double>>;
TYPED_TEST_SUITE(CameraModelDoubleTest, DoubleCases);

template <typename Camera>
void expectJacobiansMatchNumeric(const Camera& cam, const Eigen::Vector3d& p) {
  using Params = typename Camera::Params;
  Eigen::Vector2d px;
  typename Camera::Mat2x3 J_p;
  typename Camera::Mat2xP J_params;
  ASSERT_TRUE(cam.project(p, px, &J_p, &J_params));
  const auto f_p = [&](const Eigen::VectorXd& q) {
    Eigen::Vector2d out;
    EXPECT_TRUE(cam.project(Eigen::Vector3d(q), out));
    return Eigen::VectorXd(out);
  };
  const auto f_params = [&](const Eigen::VectorXd& params) {
    Eigen::Vector2d out;
    EXPECT_TRUE(Camera(Params(params)).project(p, out));
    return Eigen::VectorXd(out);
  };
  const double h = 1e-6 * p.norm();
  EXPECT_TRUE(jacobianNear(J_p, numericJacobian(f_p, p, h), 1e-5)) << "d_px_d_p at " << p.transpose();
  EXPECT_TRUE(jacobianNear(J_params, numericJacobian(f_params, cam.params(), 1e-7), 1e-5))
      << "d_px_d_params at " << p.transpose();
}

TYPED_TEST(CameraModelDoubleTest, JacobiansMatchCentralDifferences) {
  const typename TypeParam::Camera cam(TypeParam::Fixture::typical());
  const double margin = 0.02;
  int checked = 0;
  for (const Eigen::Vector3d& dir : sphereDirections(400)) {
    // Keep the finite-difference stencil inside the valid region, and the pixel within a few
    // image sizes (far outside, pixels of 1e5 and more swamp central differences in rounding).
    if (std::acos(dir.z()) > cam.maxAngle() - margin) continue;
    Eigen::Vector2d px;
    if (!cam.project(dir, px) || (px - Eigen::Vector2d(kWidth / 2, kHeight / 2)).norm() > 2 * kWidth)
      continue;
    expectJacobiansMatchNumeric(cam, dir * 2.5);
    ++checked;
  }
  expectJacobiansMatchNumeric(cam, Eigen::Vector3d(0, 0, 1));    // on the optical axis
  expectJacobiansMatchNumeric(cam, Eigen::Vector3d(1e-9, 0, 1));  // just off it
  EXPECT_GT(checked, 100);
}

/// The smallest image-space speed (px/rad) of a ray turning in any direction about its origin.
template <typename Camera>
double pixelsPerRadian(const Camera& cam, const Eigen::Vector3d& dir) {
  Eigen::Vector2d px;
  typename Camera::Mat2x3 J;
  if (!cam.project(dir, px, &J)) return 0.0;
  const Eigen::Vector3d e1 = dir.unitOrthogonal();
  const Eigen::Vector3d e2 = dir.cross(e1);
  Eigen::Matrix2d B;
  B << J * e1, J * e2;
  const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix2d>(B).singularValues();
  return sv[1];
}

TYPED_TEST(CameraModelDoubleTest, RandomParametersRoundTrip) {
  using Camera = typename TypeParam::Camera;
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const auto directions = sphereDirections(2000);
  for (int trial = 0; trial < 300; ++trial) {
    const auto params = TypeParam::Fixture::random(rng);
    ASSERT_FALSE(Camera::checkParams(params)) << *Camera::checkParams(params);
    const Camera cam(params);
    const double max_angle = cam.maxAngle();
    SCOPED_TRACE(::testing::Message() << "params " << params.transpose() << ", maxAngle " << max_angle);
    for (const Eigen::Vector3d& dir : directions) {
      const double theta = std::acos(dir.z());
      Eigen::Vector2d px;
      const bool ok = cam.project(dir, px);
      if (theta < max_angle - 1e-9) {
        ASSERT_TRUE(ok) << "θ = " << theta;
      }
      if (theta > max_angle + 1e-9) {
        ASSERT_FALSE(ok) << "θ = " << theta;
      }
      if (!ok) continue;
      // Far outside any image the pixel loses precision; the checks hold for |px| < 1e5.
      if (px.norm() > 1e5) continue;
      Eigen::Vector3d d;
      ASSERT_TRUE(cam.unproject(px, d)) << "θ = " << theta << " px " << px.transpose();
      // The angle is as good as the pixel round trip (1e-6 px) divided by the image's local
      // speed in px/rad. Near a fold, or where xi = 1e3 squeezes the sphere into a pixel, that
      // speed tends to 0 and the direction is not recoverable from the pixel: below 10 px/rad
      // only the pixel round trip (next loop) is held.
      const double speed = pixelsPerRadian(cam, dir);
      if (speed < 10.0) continue;
      const double tol = 1e-9 + 1e-6 / speed;
      ASSERT_LE(angleBetween(d, dir), tol) << "θ = " << theta << " px " << px.transpose();
    }
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector2d px(kWidth * u01(rng), kHeight * u01(rng));
      Eigen::Vector3d d;
      if (!cam.unproject(px, d)) continue;
      Eigen::Vector2d back;
      ASSERT_TRUE(cam.project(d, back)) << "px " << px.transpose();
      ASSERT_LE((back - px).norm(), 1e-6) << "px " << px.transpose();
    }
  }
}

TYPED_TEST(CameraModelDoubleTest, RandomParametersJacobians) {
  using Camera = typename TypeParam::Camera;
  std::mt19937 rng(42);
  for (int trial = 0; trial < 40; ++trial) {
    auto params = TypeParam::Fixture::random(rng);
    // Finite differences on alpha need room on both sides.
    const Camera cam(params);
    for (const Eigen::Vector3d& dir : sphereDirections(30)) {
      if (std::acos(dir.z()) > cam.maxAngle() - 0.05) continue;
      Eigen::Vector2d px;
      if (!cam.project(dir, px) || px.norm() > 1e5) continue;
      Eigen::Vector2d out;
      typename Camera::Mat2x3 J_p;
      ASSERT_TRUE(cam.project(dir, out, &J_p));
      const auto f_p = [&](const Eigen::VectorXd& q) {
        Eigen::Vector2d o;
        EXPECT_TRUE(cam.project(Eigen::Vector3d(q), o));
        return Eigen::VectorXd(o);
      };
      ASSERT_TRUE(jacobianNear(J_p, numericJacobian(f_p, dir, 1e-6), 2e-4))
          << "params " << params.transpose() << " dir " << dir.transpose();
    }
  }
}

}  // namespace
}  // namespace telesphere::test
