// SPDX-License-Identifier: MIT
/// @brief CPU tests of the spherical-rendering geometry: γ (paper eq. 4), the far ray–sphere hit
///        and its numerical stability, eye rays from XrFovf angles, the GL projection, pose and
///        settings checks, and the mode → pose mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tests/xr/render_fixtures.h"
#include "xr/render/sphere_geometry.h"

namespace telesphere::xr {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(ConstantDistanceAngularError, ZeroAtTheSphereAndWithoutTranslation) {
  for (double r : {0.01, 0.5, 1.0, 1000.0}) {
    EXPECT_EQ(render::constantDistanceAngularError(r, 0.1, r), 0.0);
    EXPECT_EQ(render::constantDistanceAngularError(3.0 * r, 0.0, r), 0.0);  // atan2(·, 0) = π/2
  }
}

TEST(ConstantDistanceAngularError, MatchesThePaperFigure) {
  // The literal eq. 4 where it has no cancellation trouble.
  for (double d : {0.1, 0.3, 1.7, 40.0})
    for (double dx : {0.01, 0.1, 0.5})
      for (double r : {0.5, 1.0, 3.0})
        EXPECT_NEAR(render::constantDistanceAngularError(d, dx, r), std::atan2(d, dx) - std::atan2(r, dx),
                    1e-15);
  // Paper Fig. 5: Δx = 10 cm, r = 1 m.
  EXPECT_NEAR(render::constantDistanceAngularError(0.3, 0.1, 1.0), std::atan(3.0) - std::atan(10.0), 1e-15);
  EXPECT_NEAR(render::constantDistanceAngularError(0.3, 0.1, 1.0) * 180 / M_PI, -12.72, 0.01);
  EXPECT_GT(render::constantDistanceAngularError(2.0, 0.1, 1.0), 0.0);  // beyond the sphere: positive
  EXPECT_LT(render::constantDistanceAngularError(0.5, 0.1, 1.0), 0.0);  // nearer: negative
  // Saturation for large d: π/2 − atan2(r, Δx).
  EXPECT_NEAR(render::constantDistanceAngularError(1e12, 0.1, 1.0), M_PI / 2 - std::atan2(1.0, 0.1), 1e-12);
}

TEST(ConstantDistanceAngularError, StableAsTranslationVanishes) {
  double previous = kInf;
  for (double dx = 1e-2; dx > 1e-300; dx *= 1e-3) {
    const double g = render::constantDistanceAngularError(2.0, dx, 1.0);
    ASSERT_TRUE(std::isfinite(g)) << dx;
    EXPECT_GE(g, 0.0);
    EXPECT_LE(g, previous);
    // Small-angle limit: γ ≈ Δx/r − Δx/d.
    if (dx < 1e-6) {
      EXPECT_NEAR(g, dx / 1.0 - dx / 2.0, 1e-9 * dx);
    }
    previous = g;
  }
}

TEST(SphereFarHit, EyeAtTheCentreHitsAtRadius) {
  for (double r : {0.01, 1.0, 1000.0}) {
    const auto t = render::sphereFarHit(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0.6, 0.8), -r * r);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, r, 1e-15 * r);
  }
}

TEST(SphereFarHit, InsideTheHitLiesOnTheSphereAhead) {
  const Eigen::Vector3d o(0.04, -0.03, 0.06);
  for (const auto& d : test::sphereDirections(500)) {
    for (double r : {0.1, 1.0, 1000.0}) {
      const auto t = render::sphereFarHit(o, d, o.squaredNorm() - r * r);
      ASSERT_TRUE(t) << d.transpose();
      EXPECT_GT(*t, 0.0);
      EXPECT_NEAR((o + *t * d).norm(), r, 1e-13 * r);
    }
  }
}

TEST(SphereFarHit, OutsideTakesTheFarSideOrMisses) {
  const double r = 0.01;
  const Eigen::Vector3d o(0, 0, -0.05);  // 5 cm behind the camera, sphere of 1 cm
  // Towards the centre: both roots ahead (0.04 and 0.06); the far one.
  auto t = render::sphereFarHit(o, Eigen::Vector3d(0, 0, 1), o.squaredNorm() - r * r);
  ASSERT_TRUE(t);
  EXPECT_NEAR(*t, 0.06, 1e-16);
  // Tangent limit: sin(half-angle) = r/|o| = 0.2. Just inside hits, just outside misses.
  const double edge = std::asin(0.2);
  for (double a : {edge - 1e-6, edge + 1e-6}) {
    const Eigen::Vector3d d(std::sin(a), 0, std::cos(a));
    t = render::sphereFarHit(o, d, o.squaredNorm() - r * r);
    EXPECT_EQ(bool(t), a < edge) << a;
    if (t) {
      EXPECT_NEAR((o + *t * d).norm(), r, 1e-15);
    }
  }
  // Sphere behind the eye: no hit.
  EXPECT_FALSE(render::sphereFarHit(o, Eigen::Vector3d(0, 0, -1), o.squaredNorm() - r * r));
}

TEST(SphereFarHit, NoCancellationForHugeRadius) {
  // |o| ≪ r: the naive (−b + sqrt(b² − c)) loses all digits of the small root; the far root
  // must still put the point on the sphere to double precision.
  const Eigen::Vector3d o(1e-3, 2e-3, -1e-3);
  const Eigen::Vector3d d = Eigen::Vector3d(0.3, -0.2, -0.9).normalized();
  const double r = 1000.0;
  const auto t = render::sphereFarHit(o, d, o.squaredNorm() - r * r);
  ASSERT_TRUE(t);
  EXPECT_NEAR((o + *t * d).norm(), r, 1e-12);
  // Eye on the surface looking outwards: the hit is the eye itself (continuous from inside).
  const Eigen::Vector3d on(0, 0, 1);
  const auto t0 = render::sphereFarHit(on, Eigen::Vector3d(0, 0, 1), 0.0);
  ASSERT_TRUE(t0);
  EXPECT_EQ(*t0, 0.0);
}

TEST(EyeRay, FollowsTheXrFovAngles) {
  const render::Fov fov{-0.6, 0.4, 0.5, -0.3};
  const int w = 101, h = 51;
  // Left and right image edges at col −0.5 and w − 0.5.
  EXPECT_NEAR(render::eyeRay(fov, w, h, -0.5, 25).x(), std::tan(-0.6), 1e-15);
  EXPECT_NEAR(render::eyeRay(fov, w, h, w - 0.5, 25).x(), std::tan(0.4), 1e-15);
  EXPECT_NEAR(render::eyeRay(fov, w, h, 50, -0.5).y(), std::tan(0.5), 1e-15);  // top row is up
  EXPECT_NEAR(render::eyeRay(fov, w, h, 50, h - 0.5).y(), std::tan(-0.3), 1e-15);
  EXPECT_EQ(render::eyeRay(fov, w, h, 3, 4).z(), -1.0);
  const render::Fov symmetric{-0.5, 0.5, 0.5, -0.5};
  EXPECT_NEAR(render::eyeRay(symmetric, w, h, 50, 25).head<2>().norm(), 0.0, 1e-15);
}

TEST(ClipFromEye, FrustumEdgesMapToNdcBounds) {
  const render::Fov fov{-0.6, 0.4, 0.5, -0.3};
  const double near = 0.05;
  const Eigen::Matrix4d P = render::clipFromEye(fov, near);
  const auto ndc = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector4d c = P * p.homogeneous();
    return Eigen::Vector3d(c.head<3>() / c.w());
  };
  EXPECT_NEAR(ndc({std::tan(-0.6) * 2, 0, -2}).x(), -1.0, 1e-14);
  EXPECT_NEAR(ndc({std::tan(0.4) * 3, 0, -3}).x(), 1.0, 1e-14);
  EXPECT_NEAR(ndc({0, std::tan(0.5) * 2, -2}).y(), 1.0, 1e-14);
  EXPECT_NEAR(ndc({0, std::tan(-0.3) * 2, -2}).y(), -1.0, 1e-14);
  EXPECT_NEAR(ndc({0, 0, -near}).z(), -1.0, 1e-14);
  EXPECT_LT(ndc({0, 0, -1}).z(), ndc({0, 0, -2}).z());  // farther → larger depth
  EXPECT_LT(ndc({0, 0, -1e6}).z(), 1.0);
}

TEST(Checks, RejectNonFiniteAndMalformedPoses) {
  EXPECT_FALSE(render::checkPose(Eigen::Isometry3d::Identity()));
  EXPECT_FALSE(render::checkPose(test::eyePose({0, 0, 0}, test::rotation(M_PI, {0, 0, 1}))));
  EXPECT_FALSE(render::checkPose(test::eyePose({0, 0, 0}, test::rotation(1e-5, {1, 0, 0}))));
  for (double bad : {kNaN, kInf, -kInf}) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().y() = bad;
    EXPECT_TRUE(render::checkPose(T)) << bad;
    T = Eigen::Isometry3d::Identity();
    T.linear()(1, 2) = bad;
    EXPECT_TRUE(render::checkPose(T)) << bad;
  }
  Eigen::Isometry3d scaled = Eigen::Isometry3d::Identity();
  scaled.linear() *= 1.01;
  EXPECT_TRUE(render::checkPose(scaled));
  Eigen::Isometry3d mirrored = Eigen::Isometry3d::Identity();
  mirrored.linear()(0, 0) = -1;
  EXPECT_TRUE(render::checkPose(mirrored));
}

TEST(Checks, RejectBadViewsAndSettings) {
  render::EyeView view;
  view.width = 64;
  view.height = 48;
  EXPECT_FALSE(render::checkEyeView(view));
  render::EyeView bad = view;
  bad.width = 0;
  EXPECT_TRUE(render::checkEyeView(bad));
  bad = view;
  bad.fov.angle_left = 0.8;  // left > right
  EXPECT_TRUE(render::checkEyeView(bad));
  bad = view;
  bad.fov.angle_up = M_PI / 2;
  EXPECT_TRUE(render::checkEyeView(bad));
  bad = view;
  bad.fov.angle_down = kNaN;
  EXPECT_TRUE(render::checkEyeView(bad));
  bad = view;
  bad.T_cam_eye.translation().x() = kNaN;
  ASSERT_TRUE(render::checkEyeView(bad));
  EXPECT_NE(render::checkEyeView(bad)->find("T_cam_eye"), std::string::npos);

  render::RenderSettings s;
  EXPECT_FALSE(render::checkRenderSettings(s));
  for (double r : {0.0, -1.0, kNaN, kInf}) {
    s.radius = r;
    EXPECT_TRUE(render::checkRenderSettings(s)) << r;
  }
  s = render::RenderSettings{};
  s.T_cam_eye_fixed.translation().z() = kInf;
  EXPECT_TRUE(render::checkRenderSettings(s));
  s = render::RenderSettings{};
  s.mesh_rings = 1;
  EXPECT_TRUE(render::checkRenderSettings(s));
  // The grid's edge slope: 0 (the nearest tile wherever tiles differ) and infinity (interpolated
  // everywhere) are settings; a negative slope or NaN is not.
  for (double slope : {0.0, render::kGridEdgeSlopePerMPerDeg, kInf}) {
    s = render::RenderSettings{};
    s.grid_edge_slope_per_m_per_deg = slope;
    EXPECT_FALSE(render::checkRenderSettings(s)) << slope;
  }
  for (double slope : {-0.1, kNaN}) {
    s.grid_edge_slope_per_m_per_deg = slope;
    ASSERT_TRUE(render::checkRenderSettings(s)) << slope;
    EXPECT_NE(render::checkRenderSettings(s)->find("edge slope"), std::string::npos);
  }
  std::string error;
  EXPECT_EQ(render::renderSettingsFromText("full6d", "exact", 1.0, &error)->grid_edge_slope_per_m_per_deg,
            render::kGridEdgeSlopePerMPerDeg);
  EXPECT_EQ(render::renderSettingsFromText("full6d", "exact", 1.0, &error, "bilinear")->grid_edge_slope_per_m_per_deg, kInf);
  EXPECT_FALSE(render::renderSettingsFromText("full6d", "exact", 1.0, &error, "sharp"));
  EXPECT_NE(error.find("grid edges must be nearest or bilinear"), std::string::npos) << error;
}

TEST(Modes, PickThePoseTheyUse) {
  render::EyeView view;
  view.T_cam_eye = test::eyePose({0.1, 0.2, 0.3}, test::rotation(0.4, {1, 1, 0}));
  render::RenderSettings s;
  s.T_cam_eye_fixed = test::eyePose({0, 0, 0.01}, test::rotation(-0.785, {1, 0, 0}));
  s.mode = link::VisualMode::kFull6d;
  EXPECT_TRUE(render::effectiveT_cam_eye(view, s).isApprox(view.T_cam_eye));
  s.mode = link::VisualMode::kOrientation3d;
  EXPECT_TRUE(render::effectiveT_cam_eye(view, s).linear().isApprox(view.T_cam_eye.linear()));
  EXPECT_EQ(render::effectiveT_cam_eye(view, s).translation(), Eigen::Vector3d::Zero());
  s.mode = link::VisualMode::kFixed;
  EXPECT_TRUE(render::effectiveT_cam_eye(view, s).isApprox(s.T_cam_eye_fixed));
  for (auto p : {render::RenderPath::kExact, render::RenderPath::kMesh, render::RenderPath::kLut})
    EXPECT_EQ(render::parseRenderPath(render::renderPathName(p)), p);
  EXPECT_FALSE(render::parseRenderPath("fast"));
}

TEST(Frames, OpticalFromViewFlipsYAndZ) {
  EXPECT_TRUE((render::kR_optical_view * render::kR_optical_view).isIdentity());
  EXPECT_EQ(render::kR_optical_view * Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, 1));  // forward
  EXPECT_EQ(render::kR_optical_view * Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, -1, 0));  // up
  EXPECT_EQ(render::kR_optical_view * Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0));   // right
}

}  // namespace
}  // namespace telesphere::xr
