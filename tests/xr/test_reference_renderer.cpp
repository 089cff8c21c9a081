// SPDX-License-Identifier: MIT
/// @brief CPU tests of the double-precision reference renderer: known pixels for known poses,
///        180° roll symmetry, the pure-rotation limit (r = 1 km), tiny spheres with the eye
///        outside, rays beyond 180°, rejection of NaN/inf poses, bilinear/YUV sampling, and the
///        measured angular error of the constant-distance assumption against γ.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tests/xr/gamma_scene.h"
#include "tests/xr/render_fixtures.h"
#include "xr/render/reference_renderer.h"
#include "xr/render/sphere_geometry.h"

namespace telesphere::xr {
namespace {

using test::eyePose;
using test::rotation;

render::EyeView smallEye(const Eigen::Isometry3d& T_cam_eye, int w = 41, int h = 31) {
  render::EyeView view;
  view.fov = {-0.6, 0.6, 0.45, -0.45};
  view.width = w;
  view.height = h;
  view.T_cam_eye = T_cam_eye;
  return view;
}

TEST(ReferenceRenderer, AlignedCentrePixelSeesThePrincipalPoint) {
  for (const auto& [name, camera] : test::allTypicalLenses()) {
    const auto p = camera.params();
    for (double r : {0.01, 1.0, 1000.0}) {
      render::RenderSettings s;
      s.radius = r;
      const auto px = render::referenceCameraPixel(camera, test::kImageWidth, test::kImageHeight,
                                           smallEye(Eigen::Isometry3d(render::kR_optical_view)), s, 20, 15);
      ASSERT_TRUE(px) << name;
      EXPECT_NEAR(px->x(), p[2], 1e-9) << name;
      EXPECT_NEAR(px->y(), p[3], 1e-9) << name;
    }
  }
}

TEST(ReferenceRenderer, Roll180MirrorsThroughThePrincipalPoint) {
  // A lens with fx = fy and radial symmetry: rolling the eye by π about the optical axis maps
  // the camera pixel c + δ that an eye pixel shows to c − δ.
  const calib::GenericCamera camera(
      calib::DoubleSphereCamera<double>((Eigen::Matrix<double, 6, 1>() << 240, 240, 479.5, 269.5,
                                         -0.18, 0.59).finished()));
  const Eigen::Vector3d head_move(0.0, 0.0, 0.05);  // along the axis: keeps the symmetry
  for (link::VisualMode mode : {link::VisualMode::kFull6d, link::VisualMode::kOrientation3d}) {
    render::RenderSettings s;
    s.mode = mode;
    const render::EyeView straight = smallEye(eyePose(head_move, Eigen::Matrix3d::Identity()));
    const render::EyeView rolled = smallEye(eyePose(head_move, rotation(M_PI, {0, 0, 1})));
    const Eigen::Vector2d c(479.5, 269.5);
    int compared = 0;
    for (int row = 0; row < 31; row += 5)
      for (int col = 0; col < 41; col += 5) {
        const auto a = render::referenceCameraPixel(camera, 960, 540, straight, s, col, row);
        const auto b = render::referenceCameraPixel(camera, 960, 540, rolled, s, col, row);
        ASSERT_EQ(bool(a), bool(b));
        if (a) {
          ++compared;
          EXPECT_LT((*a - c + (*b - c)).norm(), 1e-9) << col << "," << row;
        }
      }
    EXPECT_GT(compared, 40);
  }
}

TEST(ReferenceRenderer, HugeRadiusIsThePureRotationLimit) {
  // r = 1 km with a 7.8 cm head translation: within f·|t|/r ≈ 0.02 px of orientation3d.
  for (const auto& [name, camera] : test::allTypicalLenses()) {
    const render::EyeView view = smallEye(eyePose({0.04, -0.03, 0.06}, rotation(0.3, {1, 1, 0})));
    render::RenderSettings full, rot;
    full.radius = rot.radius = 1000.0;
    rot.mode = link::VisualMode::kOrientation3d;
    int compared = 0;
    for (int row = 0; row < view.height; ++row)
      for (int col = 0; col < view.width; ++col) {
        const auto a = render::referenceCameraPixel(camera, 960, 540, view, full, col, row);
        const auto b = render::referenceCameraPixel(camera, 960, 540, view, rot, col, row);
        if (a && b) {
          ++compared;
          EXPECT_LT((*a - *b).norm(), 0.05) << name << " " << col << "," << row;
        }
      }
    EXPECT_GT(compared, view.width * view.height / 2) << name;
  }
}

TEST(ReferenceRenderer, EyeAtTheCameraIsOrientationOnly) {
  const auto camera = test::scaledTypicalLens<calib::KannalaBrandtCamera>();
  const render::EyeView view = smallEye(eyePose({0, 0, 0}, rotation(0.7, {0, 1, 0.3})));
  for (double r : {0.01, 1.0, 1000.0}) {
    render::RenderSettings full, rot;
    full.radius = rot.radius = r;
    rot.mode = link::VisualMode::kOrientation3d;
    for (int row = 0; row < view.height; row += 3)
      for (int col = 0; col < view.width; col += 3) {
        const auto a = render::referenceCameraPixel(camera, 960, 540, view, full, col, row);
        const auto b = render::referenceCameraPixel(camera, 960, 540, view, rot, col, row);
        ASSERT_EQ(bool(a), bool(b));
        if (a) {
          EXPECT_LT((*a - *b).norm(), 1e-9);
        }
      }
  }
}

TEST(ReferenceRenderer, EyeOutsideATinySphereSeesItsFarSide) {
  // r = 1 cm, eye 5 cm behind the camera looking forward: the centre ray passes through the
  // sphere and shows its far point (0, 0, r), i.e. the principal point; rays more than
  // asin(r/|o|) ≈ 11.5° off the centre miss the sphere and get the border.
  // A 10000 px image around the principal point, so that every sphere hit is inside it.
  const calib::GenericCamera camera(
      calib::DoubleSphereCamera<double>((Eigen::Matrix<double, 6, 1>() << 240, 240, 4999.5, 4999.5,
                                         -0.18, 0.59).finished()));
  const auto p = camera.params();
  render::RenderSettings s;
  s.radius = 0.01;
  render::EyeView view = smallEye(eyePose({0, 0, -0.05}, Eigen::Matrix3d::Identity()));
  const auto centre = render::referenceCameraPixel(camera, 10000, 10000, view, s, 20, 15);
  ASSERT_TRUE(centre);
  EXPECT_NEAR(centre->x(), p[2], 1e-9);
  EXPECT_NEAR(centre->y(), p[3], 1e-9);
  EXPECT_FALSE(render::referenceCameraPixel(camera, 10000, 10000, view, s, 0, 15));  // 31° off: a miss
  // The whole image: hits exactly where the ray passes within r of the centre.
  for (int row = 0; row < view.height; ++row)
    for (int col = 0; col < view.width; ++col) {
      const Eigen::Vector3d d =
          (view.T_cam_eye.linear() * render::eyeRay(view.fov, view.width, view.height, col, row)).normalized();
      const double miss_distance = view.T_cam_eye.translation().cross(d).norm();
      if (std::abs(miss_distance - s.radius) < 1e-6) continue;
      EXPECT_EQ(bool(render::referenceCameraPixel(camera, 10000, 10000, view, s, col, row)),
                miss_distance < s.radius)
          << col << "," << row;
    }
}

TEST(ReferenceRenderer, RaysBeyond90DegreesReachFisheyePixels) {
  // Turned 100° from the optical axis, the centre ray is still inside the >180° lenses' field.
  for (const auto& [name, camera] : test::allTypicalLenses()) {
    const render::EyeView view = smallEye(eyePose({0, 0, 0}, rotation(100.0 * M_PI / 180.0, {0, 1, 0})));
    const auto px = render::referenceCameraPixel(camera, 1 << 20, 1 << 20, view, render::RenderSettings{}, 20, 15);
    EXPECT_EQ(bool(px), camera.maxAngle() > 100.0 * M_PI / 180.0) << name;
    // Straight backwards (identity R_cam_eye: −z of the eye is −z of the camera) no model has
    // a pixel: θ = π is never valid.
    EXPECT_FALSE(render::referenceCameraPixel(camera, 1 << 20, 1 << 20,
                                      smallEye(Eigen::Isometry3d::Identity()), render::RenderSettings{},
                                      20, 15))
        << name;
  }
}

TEST(ReferenceRenderer, RejectsNonFiniteInputs) {
  const auto camera = test::scaledTypicalLens<calib::DoubleSphereCamera>();
  const render::SourceImage image = render::SourceImage::pixelCoordinates(960, 540);
  render::EyeView view = smallEye(Eigen::Isometry3d(render::kR_optical_view));
  EXPECT_TRUE(render::renderReference(camera, image, view, render::RenderSettings{}));
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    render::EyeView v = view;
    v.T_cam_eye.translation().x() = bad;
    EXPECT_FALSE(render::renderReference(camera, image, v, render::RenderSettings{}));
    v = view;
    v.T_cam_eye.linear()(0, 1) = bad;
    EXPECT_FALSE(render::renderReference(camera, image, v, render::RenderSettings{}));
    render::RenderSettings s;
    s.radius = bad;
    EXPECT_FALSE(render::renderReference(camera, image, view, s));
  }
}

TEST(ReferenceRenderer, BorderColourWhereTheCameraSawNothing) {
  const auto camera = test::scaledTypicalLens<calib::PinholeRadtanCamera>();
  const render::SourceImage image = render::SourceImage::pixelCoordinates(960, 540);
  render::RenderSettings s;
  s.border_rgba = {0.25f, 0.5f, 0.75f, 0.0f};
  // Looking sideways, a pinhole camera sees nothing.
  const auto out = render::renderReference(
      camera, image, smallEye(eyePose({0, 0, 0}, rotation(M_PI / 2, {0, 1, 0}))), s);
  ASSERT_TRUE(out);
  for (int y = 0; y < out->height; ++y)
    for (int x = 0; x < out->width; ++x) EXPECT_EQ(out->at(x, y), s.border_rgba);
}

TEST(SourceImage, BilinearSampleOfPixelCoordinatesIsThePixel) {
  const render::SourceImage image = render::SourceImage::pixelCoordinates(17, 9);
  for (const Eigen::Vector2d& px : {Eigen::Vector2d(0, 0), Eigen::Vector2d(3.25, 7.5),
                                   Eigen::Vector2d(15.9, 0.1), Eigen::Vector2d(16, 8)}) {
    const Eigen::Vector4d v = image.sample(px);
    EXPECT_NEAR(v[0], px.x(), 1e-12);
    EXPECT_NEAR(v[1], px.y(), 1e-12);
    EXPECT_EQ(v[2], 0.0);
    EXPECT_EQ(v[3], 1.0);
  }
  // Clamped to the edge within the outer half pixel.
  EXPECT_NEAR(image.sample(Eigen::Vector2d(-0.4, 8.4))[0], 0.0, 1e-12);
  EXPECT_NEAR(image.sample(Eigen::Vector2d(-0.4, 8.4))[1], 8.0, 1e-12);
}

TEST(SourceImage, YuvIsJfifBt601) {
  // 4×2 image, 2×1 chroma: left half neutral grey, right half Cr = 255 (red).
  std::vector<std::uint8_t> planes = {128, 128, 128, 128, 128, 128, 128, 128,  // Y
                                      128, 128,                                // Cb
                                      128, 255};                               // Cr
  const render::SourceImage image = render::SourceImage::yuv(4, 2, 2, 1, planes);
  ASSERT_TRUE(image.consistent());
  const Eigen::Vector4d grey = image.sample(Eigen::Vector2d(0, 0));
  EXPECT_NEAR(grey[0], 128 / 255.0, 1e-12);
  EXPECT_NEAR(grey[1], 128 / 255.0, 1e-12);
  EXPECT_NEAR(grey[2], 128 / 255.0, 1e-12);
  const Eigen::Vector4d red = image.sample(Eigen::Vector2d(3, 1));
  EXPECT_NEAR(red[0], std::min(1.0, (128 + 1.402 * 127) / 255.0), 1e-12);
  EXPECT_NEAR(red[1], (128 - 0.714136 * 127) / 255.0, 1e-12);
  EXPECT_NEAR(red[2], 128 / 255.0, 1e-12);
  EXPECT_FALSE(render::SourceImage::yuv(4, 2, 2, 1, {1, 2, 3}).consistent());
}

TEST(ReferenceRenderer, MeasuredAngularErrorIsGamma) {
  const auto camera = test::scaledTypicalLens<calib::DoubleSphereCamera>();
  const double r = 1.0;
  for (double d : {0.3, 0.6, 1.0, 2.5, 10.0}) {
    const render::SourceImage plane = test::planeImage(camera, 960, 540, d);
    for (double dx : {0.02, 0.1}) {
      const render::EyeView view = test::gammaEye(dx, r);
      render::RenderSettings s;
      s.radius = r;
      const auto out = render::renderReference(camera, plane, view, s);
      ASSERT_TRUE(out);
      const Eigen::Vector4f shown = out->at(10, 10);
      const double measured = test::measuredGamma(shown[0], shown[1], d, dx, r);
      const double expected = render::constantDistanceAngularError(d, dx, r);
      EXPECT_NEAR(measured, expected, 2e-5) << "d " << d << " dx " << dx;
    }
  }
}

}  // namespace
}  // namespace telesphere::xr
