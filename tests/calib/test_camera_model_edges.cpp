// SPDX-License-Identifier: MIT
/// @brief Model-specific edges: the double sphere's validity condition beyond 90°, alpha at 0,
///        0.5 and 1, xi near 0 and large; closed-form limits (pinhole, equidistant); the exact
///        boundary of every model's valid cone; parameter checks that name the parameter.
#include <gtest/gtest.h>

#include <cmath>

#include "calib/generic_camera.h"
#include "tests/calib/camera_model_fixtures.h"

namespace telesphere::test {
namespace {

using calib::DoubleSphereCamera;
using calib::ExtendedUnifiedCamera;
using calib::GenericCamera;
using calib::KannalaBrandtCamera;
using calib::PinholeRadtanCamera;
using Ds = DoubleSphereCamera<double>;

Ds ds(double xi, double alpha) {
  return Ds((Ds::Params() << 500, 500, 640, 480, xi, alpha).finished());
}

TEST(DoubleSphereCamera, MaxAngleClosedForms) {
  EXPECT_DOUBLE_EQ(ds(0.0, 0.0).maxAngle(), M_PI / 2);  // the pinhole: a 180° field of view
  EXPECT_DOUBLE_EQ(ds(0.0, 0.5).maxAngle(), M_PI);      // w2 = 1: everything but the back axis
  EXPECT_DOUBLE_EQ(ds(0.7, 0.5).maxAngle(), M_PI);
  // alpha = 1: w1 = 0, w2 = xi/sqrt(xi² + 1)
  EXPECT_NEAR(ds(0.3, 1.0).maxAngle(), std::acos(-0.3 / std::sqrt(1.09)), 1e-15);
  // xi > 1: Usenko's bound acos(−w2) is too wide; at alpha = 1 the image radius
  // sin θ/sqrt(1 + 2·xi·cos θ + xi²) peaks where cos θ = −1/xi, and validity ends there.
  EXPECT_NEAR(ds(2.0, 1.0).maxAngle(), std::acos(-0.5), 1e-9);
  EXPECT_NEAR(ds(1e3, 1.0).maxAngle(), std::acos(-1e-3), 1e-9);
  // xi < 0, alpha = 0: den = xi + cos θ reaches 0 at cos θ = −xi before the w2 bound.
  EXPECT_NEAR(ds(-0.13, 0.0).maxAngle(), std::acos(0.13), 1e-9);
  EXPECT_GT(ds(-0.18, 0.59).maxAngle(), M_PI / 2);  // the paper's kind of lens: beyond 180°
}

TEST(DoubleSphereCamera, ValidityIsExactAtTheBoundary) {
  for (double alpha : {0.0, 0.25, 0.5, 0.59, 0.75, 1.0}) {
    for (double xi : {-0.9, -0.18, 0.0, 1e-9, 0.5, 3.0, 1e3}) {
      const Ds cam = ds(xi, alpha);
      const double t = cam.maxAngle();
      Eigen::Vector2d px;
      SCOPED_TRACE(::testing::Message() << "xi " << xi << " alpha " << alpha << " maxAngle " << t);
      for (double phi : {0.0, 1.0, 2.5}) {
        if (t < M_PI - 1e-7) {
          EXPECT_TRUE(cam.project(directionAt(t - 1e-7, phi), px));
          EXPECT_FALSE(cam.project(directionAt(t + 1e-7, phi), px));
        }
        EXPECT_FALSE(cam.project(Eigen::Vector3d(0, 0, -1), px)) << "the backward axis";
      }
      EXPECT_FALSE(cam.project(Eigen::Vector3d::Zero(), px)) << "the camera centre";
    }
  }
}

TEST(DoubleSphereCamera, AlphaZeroXiZeroIsThePinhole) {
  const PinholeRadtanCamera<double> pin(
      (PinholeRadtanCamera<double>::Params() << 500, 500, 640, 480, 0, 0, 0, 0).finished());
  const ExtendedUnifiedCamera<double> eucm(
      (ExtendedUnifiedCamera<double>::Params() << 500, 500, 640, 480, 0, 1).finished());
  const Ds cam = ds(0.0, 0.0);
  for (const Eigen::Vector3d& dir : sphereDirections(2000)) {
    Eigen::Vector2d a, b, c;
    const bool ok = cam.project(dir, a);
    EXPECT_EQ(ok, pin.project(dir, b));
    EXPECT_EQ(ok, eucm.project(dir, c));
    if (ok && a.norm() < 1e6) {
      EXPECT_NEAR((a - b).norm(), 0.0, 1e-9 * (1 + a.norm()));
      EXPECT_NEAR((a - c).norm(), 0.0, 1e-9 * (1 + a.norm()));
    }
  }
}

TEST(DoubleSphereCamera, AlphaAboveHalfBoundsTheImageCircle) {
  const Ds cam = ds(0.3, 0.75);
  const double r_max = 500.0 / std::sqrt(2 * 0.75 - 1);  // pixels from the centre
  Eigen::Vector3d d;
  EXPECT_FALSE(cam.unproject(Eigen::Vector2d(640 + r_max * (1 + 1e-9), 480), d));
  EXPECT_TRUE(d.isZero());
  // The edge of the valid cone lies inside the circle and unprojects to itself.
  Eigen::Vector2d px;
  ASSERT_TRUE(cam.project(directionAt(cam.maxAngle() - 1e-9, 0.0), px));
  EXPECT_LT(px.x() - 640, r_max);
  ASSERT_TRUE(cam.unproject(px, d));
  EXPECT_NEAR(std::acos(d.z()), cam.maxAngle() - 1e-9, 1e-6);
}

TEST(KannalaBrandtCamera, ZeroCoefficientsAreEquidistant) {
  const KannalaBrandtCamera<double> cam(
      (KannalaBrandtCamera<double>::Params() << 400, 400, 640, 480, 0, 0, 0, 0).finished());
  EXPECT_DOUBLE_EQ(cam.maxAngle(), M_PI);
  for (double theta : {0.0, 0.3, M_PI / 2, 2.5, M_PI - 1e-6}) {
    Eigen::Vector2d px;
    ASSERT_TRUE(cam.project(directionAt(theta, 0.0), px)) << theta;
    EXPECT_NEAR(px.x(), 640 + 400 * theta, 1e-6);
  }
  Eigen::Vector2d px;
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0, 0, -1), px)) << "θ = π has no direction";
}

TEST(KannalaBrandtCamera, FoldingPolynomialLimitsTheAngle) {
  // dθd/dθ = 1 − 0.3·θ² vanishes at θ = 1/sqrt(0.3).
  const KannalaBrandtCamera<double> cam(
      (KannalaBrandtCamera<double>::Params() << 400, 400, 640, 480, -0.1, 0, 0, 0).finished());
  EXPECT_NEAR(cam.maxAngle(), 1 / std::sqrt(0.3), 1e-12);
  Eigen::Vector2d px;
  EXPECT_TRUE(cam.project(directionAt(cam.maxAngle() - 1e-9, 0.3), px));
  EXPECT_FALSE(cam.project(directionAt(cam.maxAngle() + 1e-9, 0.3), px));
}

TEST(PinholeRadtanCamera, ValidOnlyInFrontAndInsideTheMonotonicRadius) {
  // 1 + 3·k1·r² = 0 at r² = 1/0.6 for k1 = −0.2, k2 = 0.
  const PinholeRadtanCamera<double> cam(
      (PinholeRadtanCamera<double>::Params() << 500, 500, 640, 480, -0.2, 0, 0, 0).finished());
  EXPECT_NEAR(cam.maxAngle(), std::atan(std::sqrt(1 / 0.6)), 1e-12);
  Eigen::Vector2d px;
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0, 0, 0), px));
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0.1, 0, -1), px));
  EXPECT_FALSE(cam.project(Eigen::Vector3d(1, 0, 0), px)) << "exactly sideways";
  EXPECT_TRUE(cam.project(directionAt(cam.maxAngle() - 1e-9, 1.0), px));
  EXPECT_FALSE(cam.project(directionAt(cam.maxAngle() + 1e-9, 1.0), px));
}

TEST(CameraParams, ErrorsNameTheParameter) {
  EXPECT_EQ(*Ds::checkParams((Ds::Params() << 500, 500, 640, 480, 0.1, 1.3).finished()),
            "alpha = 1.3 is outside [0, 1]");
  EXPECT_EQ(*Ds::checkParams((Ds::Params() << -1, 500, 640, 480, 0.1, 0.5).finished()),
            "fx = -1 must be a finite number > 0");
  EXPECT_EQ(*Ds::checkParams((Ds::Params() << 500, 500, 640, 480, -1, 0.5).finished()),
            "xi = -1 is outside (-1, 1000]");
  EXPECT_TRUE(Ds::checkParams((Ds::Params() << 500, 500, 640, NAN, 0.1, 0.5).finished())
                  ->starts_with("cy = nan"));
  EXPECT_FALSE(Ds::checkParams((Ds::Params() << 500, 500, 640, 480, 0, 0).finished()));
  EXPECT_FALSE(Ds::checkParams((Ds::Params() << 500, 500, 640, 480, 0, 1).finished()));
}

TEST(GenericCamera, CreatesEveryModelByNameAndRejectsBadInput) {
  std::string error;
  for (std::string_view name : GenericCamera::modelNames()) {
    const auto n = GenericCamera::paramNames(name).size();
    Eigen::VectorXd p = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
    p.head<4>() << 500, 500, 640, 480;
    if (name == "eucm") p[5] = 1.0;
    const auto cam = GenericCamera::create(name, p, &error);
    ASSERT_TRUE(cam) << name << ": " << error;
    EXPECT_EQ(cam->modelName(), name);
    EXPECT_EQ(cam->params(), p);
    Eigen::Vector2d px;
    ASSERT_TRUE(cam->project(Eigen::Vector3d(0, 0, 1), px));
    EXPECT_EQ(px, Eigen::Vector2d(640, 480));
  }
  EXPECT_FALSE(GenericCamera::create("omni", Eigen::VectorXd::Zero(5), &error));
  EXPECT_EQ(error, "unknown camera model \"omni\" (known: ds, eucm, kb4, pinhole)");
  EXPECT_FALSE(GenericCamera::create("ds", Eigen::VectorXd::Zero(4), &error));
  EXPECT_EQ(error, "model \"ds\" takes 6 parameters [fx, fy, cx, cy, xi, alpha], got 4");
}

}  // namespace
}  // namespace telesphere::test
