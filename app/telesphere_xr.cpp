// SPDX-License-Identifier: MIT
/// @brief telesphere-xr: the operator side. Commands:
///   still --calib FILE --camera N --image IMG --T-cam-eye "tx ty tz qx qy qz qw"
///         --fov "left right up down" --size WxH --radius R --mode full6d|orientation3d|fixed
///         --path exact|mesh|lut --out PNG [--border "r g b a"]
/// renders what the operator's eye would see of one camera image (xr/README.md), offscreen on
/// an EGL surfaceless context (no display or GPU needed). Exit codes: 0 ok, 1 bad arguments or
/// input, 2 no GL context, 3 rendering or writing failed.
///   openxr --calib FILE [--port P] | --test-scene   [--frames N] [--readback-dir DIR] [--out DIR]
///          [--radius R] [--mode M] [--path P] [--swapchain-colour auto|srgb|linear] [--reconnect S]
/// the operator app in a headset (app/xr_openxr_command.h, xr/README.md "OpenXR session").
///   desktop --calib FILE [--port P] [--eye-size WxH] [--window-size WxH] [--duration S] [--out DIR]
/// the operator app in a window, mouse and keyboard move the head (app/xr_desktop_command.h).
///   offscreen --calib FILE [--port P] [--trajectory CSV] [--eye-size WxH] [--duration S] [--out DIR]
/// the operator loop without a headset: frames from telesphere-robot, head poses from a trajectory,
/// both eyes rendered offscreen at the display rate (app/xr_offscreen_command.h).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/xr_desktop_command.h"
#include "app/xr_offscreen_command.h"
#include "app/xr_openxr_command.h"
#include "calib/calibration_file.h"
#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "shaders/png_io.h"
#include "xr/render/spherical_renderer.h"

namespace {

using namespace telesphere;

/// Exactly `count` whitespace-separated numbers from `text` (strtod syntax, so "nan" and "inf"
/// parse and are then refused by the checks with a reason), or nothing.
std::optional<std::vector<double>> numbers(const std::string& text, std::size_t count) {
  std::istringstream in(text);
  std::vector<double> out;
  std::string token;
  while (in >> token) {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size()) return std::nullopt;
    out.push_back(v);
  }
  if (out.size() != count) return std::nullopt;
  return out;
}

int fail(int code, const std::string& message) {
  std::cerr << "telesphere-xr still: " << message << "\n";
  return code;
}

struct StillOptions {
  std::string calib, image, pose, fov, size = "1440x1600", mode = "full6d", path = "exact", out;
  std::string border = "0 0 0 1";
  int camera = 0;
  double radius = 1.0;
};

int runStill(const StillOptions& o) {
  auto calibration = calib::loadCalibrationFile(o.calib);
  if (!calibration) return fail(1, calibration.error().describe());
  if (o.camera < 0 || o.camera >= int(calibration->cameras.size()))
    return fail(1, "--camera " + std::to_string(o.camera) + ": the calibration has " +
                       std::to_string(calibration->cameras.size()) + " camera(s)");
  const calib::CameraCalibration& cam = calibration->cameras[std::size_t(o.camera)];

  const auto pose = numbers(o.pose, 7);
  if (!pose) return fail(1, "--T-cam-eye needs 7 numbers \"tx ty tz qx qy qz qw\", got \"" + o.pose + "\"");
  const Eigen::Quaterniond q((*pose)[6], (*pose)[3], (*pose)[4], (*pose)[5]);
  if (!(std::abs(q.norm() - 1.0) < 1e-3))
    return fail(1, "--T-cam-eye quaternion is not unit length (|q| = " + std::to_string(q.norm()) + ")");
  xr::render::EyeView view;
  view.T_cam_eye = Eigen::Isometry3d::Identity();
  view.T_cam_eye.linear() = q.normalized().toRotationMatrix();
  view.T_cam_eye.translation() << (*pose)[0], (*pose)[1], (*pose)[2];

  const auto fov = numbers(o.fov, 4);
  if (!fov) return fail(1, "--fov needs 4 angles \"left right up down\" (rad), got \"" + o.fov + "\"");
  view.fov = {(*fov)[0], (*fov)[1], (*fov)[2], (*fov)[3]};
  char x = 0;
  std::istringstream size(o.size);
  if (!(size >> view.width >> x >> view.height) || x != 'x' || !size.eof())
    return fail(1, "--size must be WIDTHxHEIGHT, got \"" + o.size + "\"");

  std::string settings_error;
  auto parsed = xr::render::renderSettingsFromText(o.mode, o.path, o.radius, &settings_error);
  if (!parsed) return fail(1, settings_error);
  xr::render::RenderSettings settings = *parsed;
  const auto border = numbers(o.border, 4);
  if (!border) return fail(1, "--border needs 4 numbers \"r g b a\" in 0..1");
  settings.border_rgba << float((*border)[0]), float((*border)[1]), float((*border)[2]), float((*border)[3]);
  if (auto e = xr::render::checkEyeView(view)) return fail(1, *e);
  if (auto e = xr::render::checkRenderSettings(settings)) return fail(1, *e);

  cv::Mat bgr = cv::imread(o.image, cv::IMREAD_COLOR);
  if (bgr.empty()) return fail(1, o.image + ": cannot read the image");
  if (bgr.cols != cam.width || bgr.rows != cam.height)
    return fail(1, o.image + ": image is " + std::to_string(bgr.cols) + "x" +
                       std::to_string(bgr.rows) + ", camera " + std::to_string(o.camera) +
                       " is calibrated for " + std::to_string(cam.width) + "x" +
                       std::to_string(cam.height));
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  std::vector<std::uint8_t> bytes(rgb.total() * 3);
  for (int r = 0; r < rgb.rows; ++r)
    std::copy_n(rgb.ptr<std::uint8_t>(r), std::size_t(rgb.cols) * 3,
                bytes.begin() + std::ptrdiff_t(std::size_t(r) * rgb.cols * 3));

  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  if (!context) return fail(2, "no OpenGL 4.5 context: " + error);
  xr::render::GpuCamera gpu(cam.camera, cam.width, cam.height);
  if (!gpu.upload(xr::render::SourceImage::rgb8(cam.width, cam.height, std::move(bytes)), &error))
    return fail(1, error);
  xr::render::SphericalRenderer renderer;
  gl::OffscreenTarget target(view.width, view.height, GL_RGBA8);
  if (!target.complete()) return fail(3, "cannot create a " + o.size + " offscreen target");
  if (!renderer.render(gpu, view, settings, target.framebuffer(), &error)) return fail(3, error);
  const auto pixels = target.readRgba8();
  if (!gl::writePng(o.out, view.width, view.height, 4, pixels.data(), &error)) return fail(3, error);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"telesphere-xr: the operator's view of the robot's cameras"};
  app.require_subcommand(1);
  StillOptions o;
  CLI::App* still = app.add_subcommand(
      "still", "render one eye view of a camera image projected on the sphere, to PNG");
  still->add_option("--calib", o.calib, "calibration file (ours, kalibr camchain or Basalt)")->required();
  still->add_option("--camera", o.camera, "camera index in the calibration (0 = cam_l)");
  still->add_option("--image", o.image, "camera image (PNG, JPEG, ...) at the calibrated size")->required();
  still->add_option("--T-cam-eye", o.pose,
                    "\"tx ty tz qx qy qz qw\": eye pose in the camera optical frame (m); eye frame "
                    "in the OpenXR view convention (x right, y up, -z forward)")
      ->required();
  still->add_option("--fov", o.fov, "\"left right up down\" (rad), OpenXR XrFovf angles")->required();
  still->add_option("--size", o.size, "render size WxH (px)")->capture_default_str();
  still->add_option("--radius", o.radius, "sphere radius r (m)")->capture_default_str();
  still->add_option("--mode", o.mode, "full6d | orientation3d | fixed")->capture_default_str();
  still->add_option("--path", o.path, "exact | mesh | lut")->capture_default_str();
  still->add_option("--border", o.border, "\"r g b a\" (0..1) where the camera saw nothing")
      ->capture_default_str();
  still->add_option("--out", o.out, "output PNG (RGBA)")->required();
  int code = 0;
  still->callback([&] { code = runStill(o); });

  // Every mode that talks to the robot needs --keys or --insecure (DESIGN.md §10); the built-in
  // test scene and the offline replay do not talk to it.
  std::optional<telesphere::app::InsecureLinkWarning> insecure_warning;
  const auto linkReady = [&](telesphere::app::VideoLinkOptions& link, bool uses_robot) {
    if (!uses_robot) return true;
    std::string error;
    if (!telesphere::app::checkVideoLinkOptions(link, &error)) {
      std::cerr << "telesphere-xr: " << error << '\n';
      code = 1;
      return false;
    }
    insecure_warning.emplace(link.security.insecure, "telesphere-xr");
    return true;
  };
  telesphere::app::OpenXrCommandOptions openxr_options;
  telesphere::app::addOpenXrCommand(app, openxr_options)->callback([&] {
    if (linkReady(openxr_options.link, !openxr_options.test_scene))
      code = telesphere::app::runOpenXrCommand(openxr_options);
  });

  telesphere::app::DesktopCommandOptions desktop_options;
  telesphere::app::addDesktopCommand(app, desktop_options)->callback([&] {
    if (linkReady(desktop_options.link, true)) code = telesphere::app::runDesktopCommand(desktop_options);
  });

  telesphere::app::OffscreenCommandOptions offscreen_options;
  telesphere::app::addOffscreenCommand(app, offscreen_options)->callback([&] {
    if (linkReady(offscreen_options.link, offscreen_options.replay.empty()))
      code = telesphere::app::runOffscreenCommand(offscreen_options);
  });
  CLI11_PARSE(app, argc, argv);
  return code;
}
