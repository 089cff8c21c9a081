// SPDX-License-Identifier: MIT
/// @brief telesphere-xr: the operator side. Commands:
///   still --calib FILE --camera N --image IMG --T-cam-eye "tx ty tz qx qy qz qw"
///         --fov "left right up down" --size WxH --radius R --mode full6d|orientation3d|fixed
///         --path exact|mesh|lut --out PNG [--border "r g b a"]
/// renders what the operator's eye would see of one camera image (xr/README.md), offscreen on
/// an EGL surfaceless context (no display or GPU needed). Exit codes: 0 ok, 1 bad arguments or
/// input, 2 no GL context, 3 rendering or writing failed.
///   openxr [--frames N] [--readback-dir DIR] [--radius R] [--mode M] [--path P]
///          [--swapchain-colour auto|srgb|linear]
/// runs an OpenXR session (xr/README.md, "OpenXR session") showing the test scene through the
/// spherical renderer. Exit codes: 0 ok, 1 bad arguments, 2 no GL context, 3 an OpenXR call or
/// rendering failed, 4 the runtime went away during the session, 5 no OpenXR runtime.
///   offscreen --calib FILE [--port P] [--trajectory CSV] [--eye-size WxH] [--duration S] [--out DIR]
/// the operator loop without a headset: frames from telesphere-robot, head poses from a trajectory,
/// both eyes rendered offscreen at the display rate (app/xr_offscreen_command.h).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <thread>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/xr_offscreen_command.h"
#include "calib/calibration_file.h"
#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "shaders/png_io.h"
#include "xr/openxr_session.h"
#include "xr/openxr_test_scene.h"
#include "xr/spherical_renderer.h"

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
  xr::EyeView view;
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
  auto parsed = xr::renderSettingsFromText(o.mode, o.path, o.radius, &settings_error);
  if (!parsed) return fail(1, settings_error);
  xr::RenderSettings settings = *parsed;
  const auto border = numbers(o.border, 4);
  if (!border) return fail(1, "--border needs 4 numbers \"r g b a\" in 0..1");
  settings.border_rgba << float((*border)[0]), float((*border)[1]), float((*border)[2]), float((*border)[3]);
  if (auto e = xr::checkEyeView(view)) return fail(1, *e);
  if (auto e = xr::checkRenderSettings(settings)) return fail(1, *e);

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
  xr::GpuCamera gpu(cam.camera, cam.width, cam.height);
  if (!gpu.upload(xr::SourceImage::rgb8(cam.width, cam.height, std::move(bytes)), &error))
    return fail(1, error);
  xr::SphericalRenderer renderer;
  gl::OffscreenTarget target(view.width, view.height, GL_RGBA8);
  if (!target.complete()) return fail(3, "cannot create a " + o.size + " offscreen target");
  if (!renderer.render(gpu, view, settings, target.framebuffer(), &error)) return fail(3, error);
  const auto pixels = target.readRgba8();
  if (!gl::writePng(o.out, view.width, view.height, 4, pixels.data(), &error)) return fail(3, error);
  return 0;
}

// ---- openxr --------------------------------------------------------------------------------

volatile std::sig_atomic_t g_openxr_interrupted = 0;

void onOpenXrInterrupt(int) { g_openxr_interrupted = 1; }

struct OpenXrCommandOptions {
  int frames = 0;  // 0: until SIGINT or the runtime ends the session
  std::string readback_dir;
  std::string mode = "full6d", path = "exact", colour = "auto";
  double radius = 1.0;
  double exit_timeout_s = 5.0;
};

int openXrFail(int code, const std::string& message) {
  std::cerr << "telesphere-xr openxr: " << message << "\n";
  return code;
}

/// Reads the framebuffer's colour attachment 0 as RGBA8 rows top first.
std::vector<std::uint8_t> openXrReadRgba(GLuint framebuffer, int width, int height) {
  std::vector<std::uint8_t> bottom_up(std::size_t(width) * std::size_t(height) * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  std::vector<std::uint8_t> top_down(bottom_up.size());
  const std::size_t row = std::size_t(width) * 4;
  for (int y = 0; y < height; ++y)
    std::copy_n(bottom_up.begin() + std::ptrdiff_t(std::size_t(height - 1 - y) * row), row,
                top_down.begin() + std::ptrdiff_t(std::size_t(y) * row));
  return top_down;
}

std::string openXrStates(const xr::SessionStateMachine& machine) {
  std::string text;
  for (const xr::SessionState s : machine.history()) {
    if (!text.empty()) text.append(" ");
    text.append(xr::sessionStateName(s));
  }
  return text.empty() ? "(none)" : text;
}

int runOpenXr(const OpenXrCommandOptions& o) {
  std::string settings_error;
  const auto parsed = xr::renderSettingsFromText(o.mode, o.path, o.radius, &settings_error);
  if (!parsed) return openXrFail(1, settings_error);
  const xr::RenderSettings settings = *parsed;
  xr::OpenXrOptions options;
  if (o.colour == "auto") options.colour = xr::SwapchainColour::kAuto;
  else if (o.colour == "srgb") options.colour = xr::SwapchainColour::kSrgb;
  else if (o.colour == "linear") options.colour = xr::SwapchainColour::kLinear;
  else return openXrFail(1, "--swapchain-colour must be auto, srgb or linear, got \"" + o.colour + "\"");
  if (o.frames < 0) return openXrFail(1, "--frames must be >= 0");

  std::ofstream pose_log;
  if (!o.readback_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.readback_dir, ec);
    if (ec) return openXrFail(1, o.readback_dir + ": cannot create the folder: " + ec.message());
    pose_log.open(o.readback_dir + "/poses.csv");
    if (!pose_log) return openXrFail(1, o.readback_dir + "/poses.csv: cannot write");
    pose_log << "frame,eye,predicted_display_time_ns,tx,ty,tz,qx,qy,qz,qw,"
                "angle_left,angle_right,angle_up,angle_down,width,height,srgb_swapchain,png\n";
    pose_log << std::setprecision(17);
  }

  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  if (!context) return openXrFail(2, "no OpenGL 4.5 context: " + error);

  xr::OpenXrFailure failure = xr::OpenXrFailure::kNone;
  auto session = xr::OpenXrSession::create(options, &error, &failure);
  if (!session) return openXrFail(failure == xr::OpenXrFailure::kNoRuntime ? 5 : 3, error);
  std::cout << "runtime: " << session->runtimeName() << "; system: " << session->systemName()
            << "; binding: " << session->graphicsBinding() << "; space: " << session->referenceSpace()
            << "; swapchain: " << xr::glFormatName(session->swapchainFormat().format) << " "
            << session->eyeWidth() << "x" << session->eyeHeight() << " per eye" << std::endl;

  xr::GpuCamera camera(xr::OpenXrTestScene::camera(), xr::OpenXrTestScene::kImageWidth,
                       xr::OpenXrTestScene::kImageHeight);
  if (!camera.upload(xr::OpenXrTestScene::image(), &error)) return openXrFail(3, error);
  xr::SphericalRenderer renderer;
  if (!renderer.prepare(camera, settings.path, &error)) return openXrFail(3, error);

  std::signal(SIGINT, onOpenXrInterrupt);
  std::signal(SIGTERM, onOpenXrInterrupt);

  std::optional<Eigen::Isometry3d> T_vr_nom;
  const Eigen::Isometry3d T_cam_nom(xr::kR_optical_view);
  std::uint64_t waited = 0, submitted = 0, not_rendered = 0;
  std::string render_error;
  // The nominal pose: the HMD pose of the first rendered frame with pitch and roll removed.
  auto render_eye = [&](const xr::OpenXrEye& eye) {
    xr::EyeView view;
    view.fov = eye.fov;
    view.width = eye.width;
    view.height = eye.height;
    if (!T_vr_nom) T_vr_nom = xr::yawOnlyPose(eye.T_vr_hmd);
    view.T_cam_eye = T_cam_nom * T_vr_nom->inverse() * eye.T_vr_eye;
    if (!renderer.render(camera, view, settings, eye.framebuffer, &render_error)) return false;
    if (pose_log.is_open()) {
      const Eigen::Quaterniond q(view.T_cam_eye.linear());
      const Eigen::Vector3d t = view.T_cam_eye.translation();
      char png[64];
      std::snprintf(png, sizeof png, "frame%05llu_eye%d.png",
                    static_cast<unsigned long long>(eye.frame_index), eye.eye);
      pose_log << eye.frame_index << "," << eye.eye << "," << eye.predicted_display_time_ns << ","
               << t.x() << "," << t.y() << "," << t.z() << "," << q.x() << "," << q.y() << ","
               << q.z() << "," << q.w() << "," << view.fov.angle_left << "," << view.fov.angle_right
               << "," << view.fov.angle_up << "," << view.fov.angle_down << "," << eye.width << ","
               << eye.height << "," << (eye.srgb_swapchain ? 1 : 0) << "," << png << "\n";
    }
    return true;
  };
  std::string write_error;
  auto read_back = [&](const xr::OpenXrEye& eye) {
    if (o.readback_dir.empty()) return;
    char png[64];
    std::snprintf(png, sizeof png, "/frame%05llu_eye%d.png",
                  static_cast<unsigned long long>(eye.frame_index), eye.eye);
    const auto pixels = openXrReadRgba(eye.framebuffer, eye.width, eye.height);
    if (!gl::writePng(o.readback_dir + png, eye.width, eye.height, 4, pixels.data(), &write_error))
      std::cerr << "telesphere-xr openxr: " << write_error << "\n";
  };

  int code = 0;
  std::optional<std::chrono::steady_clock::time_point> exit_asked;
  bool interrupted_reported = false;
  while (true) {
    const bool want_exit = g_openxr_interrupted != 0 || (o.frames > 0 && submitted >= std::uint64_t(o.frames));
    if (want_exit && !exit_asked) {
      if (g_openxr_interrupted != 0 && !interrupted_reported) {
        std::cout << "interrupted: ending the session" << std::endl;
        interrupted_reported = true;
      }
      exit_asked = std::chrono::steady_clock::now();
      if (!session->requestExit(&error) && !session->lost()) {
        code = openXrFail(3, error);
        break;
      }
    }
    if (exit_asked && std::chrono::steady_clock::now() - *exit_asked >
                          std::chrono::duration<double>(o.exit_timeout_s)) {
      std::cerr << "telesphere-xr openxr: the runtime did not end the session within "
                << o.exit_timeout_s << " s of xrRequestExitSession; destroying it\n";
      break;
    }
    if (!session->pollEvents(&error)) {
      if (!session->lost()) { code = openXrFail(3, error); break; }
    }
    if (session->lost()) {
      code = openXrFail(4, "the OpenXR runtime went away during the session (" +
                               (error.empty() ? std::string("instance loss pending") : error) +
                               "); start the runtime again and rerun");
      break;
    }
    if (session->state().finished()) break;
    if (!session->state().shouldSyncFrames()) {
      // Not running yet (or no longer): events arrive without frames; poll at 100 Hz.
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      continue;
    }
    xr::OpenXrFrameResult frame;
    render_error.clear();
    if (!session->frame(render_eye, read_back, &frame, &error)) {
      if (session->lost()) {
        code = openXrFail(4, "the OpenXR runtime went away during the session (" + error +
                                 "); start the runtime again and rerun");
      } else {
        code = openXrFail(3, error);
      }
      break;
    }
    if (!render_error.empty()) { code = openXrFail(3, render_error); break; }
    if (frame.waited) ++waited;
    if (frame.submitted) ++submitted;
    else if (frame.waited) ++not_rendered;
  }
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  std::cout << "frames: requested " << o.frames << ", waited " << waited << ", submitted "
            << submitted << " with a projection layer, " << not_rendered
            << " ended without layers (not visible or pose invalid)\n";
  std::cout << "states: " << openXrStates(session->state()) << "\n";
  std::cout << "focused: " << (session->state().reached(xr::SessionState::kFocused) ? "yes" : "no")
            << std::endl;
  session.reset();
  return code;
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

  OpenXrCommandOptions x;
  CLI::App* openxr = app.add_subcommand(
      "openxr", "run an OpenXR session (headset or Monado) showing the test scene");
  openxr->add_option("--frames", x.frames, "end the session after N submitted frames (0: until Ctrl-C)")
      ->capture_default_str();
  openxr->add_option("--readback-dir", x.readback_dir,
                     "save every swapchain image as PNG plus poses.csv (the T_cam_eye, fov and "
                     "size each image was rendered with) here");
  openxr->add_option("--radius", x.radius, "sphere radius r (m)")->capture_default_str();
  openxr->add_option("--mode", x.mode, "full6d | orientation3d | fixed")->capture_default_str();
  openxr->add_option("--path", x.path, "exact | mesh | lut")->capture_default_str();
  openxr->add_option("--swapchain-colour", x.colour,
                     "auto | srgb | linear: swapchain format kind (auto prefers sRGB)")
      ->capture_default_str();
  openxr->add_option("--exit-timeout", x.exit_timeout_s,
                     "seconds to wait for the runtime to end the session after an exit request")
      ->capture_default_str();
  openxr->callback([&] { code = runOpenXr(x); });

  telesphere::app::OffscreenCommandOptions offscreen_options;
  telesphere::app::addOffscreenCommand(app, offscreen_options)->callback([&] {
    code = telesphere::app::runOffscreenCommand(offscreen_options);
  });
  CLI11_PARSE(app, argc, argv);
  return code;
}
