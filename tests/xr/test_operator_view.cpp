// SPDX-License-Identifier: MIT
/// @brief OperatorView against a real LinkServer on loopback and a real GL context (EGL
///        surfaceless): the border colour before any frame; head targets reach the robot with
///        the predicted display time; the robot's mode, radius and nominal mapping are followed,
///        and nonsense in the robot state (unknown mode, NaN or negative radius) is not; the
///        operator's requests reach the robot's control handler (next mode, radius steps clamped
///        to the accepted range); silence from the robot is measured; with the depth hold a new
///        image waits for its own pair's depth.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "tests/eventually.h"
#include "calib/calibration_file.h"
#include "calib/system_calibration_yaml.h"
#include "robot/link/link_pose.h"
#include "robot/link/link_server.h"
#include "robot/link/link_tap.h"
#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "xr/frame_loop/trial_indicator.h"
#include "shaders/offscreen_target.h"
#include "tests/xr/jpeg_test_images.h"
#include "xr/frame_loop/operator_view.h"

namespace telesphere::xr {
namespace {

using namespace std::chrono_literals;

link::LinkEndpoints operatorViewEndpoints() {
  link::LinkEndpoints e;
  e.base_port = 27380;
  return e;
}

class OperatorViewTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    context_ = gl::EglContext::createSurfaceless(&error);
    ASSERT_TRUE(context_) << error;
    auto calibration = calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
    ASSERT_TRUE(calibration) << calibration.error().describe();
    server_ = std::make_unique<link::LinkServer>(operatorViewEndpoints());
    robot_calibration_ = *calibration;
    server_->setControlHandler([this](const link::proto::ControlRequest& r) {
      std::lock_guard lock(mutex_);
      requests_.push_back(r);
      link::proto::ControlReply reply;
      reply.set_ok(true);
      if (r.get_calibration() && calibration_unanswered_) {  // a robot that does not answer it (yet)
        reply.set_ok(false);
        reply.set_error("busy");
        return reply;
      }
      if (r.get_calibration()) {  // the robot's calibration in use (here: generation 2)
        reply.mutable_calibration()->set_generation(2);
        reply.mutable_calibration()->set_yaml(calib::toSystemCalibrationYaml(robot_calibration_));
        reply.mutable_calibration()->set_source("test");
      }
      return reply;
    });
    makeView();
    target_ = std::make_unique<gl::OffscreenTarget>(32, 32);
    eye_.width = eye_.height = 32;
    eye_.fov = {-0.5, 0.5, 0.5, -0.5};
  }

  /// A new view (the old one closed first: the same ports) with the fixture's options, changed by `change`.
  void makeView(const std::function<void(frame_loop::OperatorViewOptions&)>& change = {}) {
    view_.reset();
    frame_loop::OperatorViewOptions options;
    options.endpoints = operatorViewEndpoints();
    options.render.border_rgba << 0.0f, 0.0f, 1.0f, 1.0f;
    options.hold_measured_s = 0.3;
    if (change) change(options);
    view_ = std::make_unique<frame_loop::OperatorView>(robot_calibration_, options);
  }

  /// Publishes a new frame and displays frames until it is on show (published again, as a new
  /// frame, when it has not arrived within 300 ms); false after 10 s.
  bool showNextFrame() {
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < deadline) {
      publishFrame();
      const std::uint64_t sequence = sequence_;
      const auto republish = std::chrono::steady_clock::now() + 300ms;
      while (std::chrono::steady_clock::now() < republish) {
        shownFrame();
        if (view_->frame() && view_->frame()->frame.sequence() == sequence) return true;
        std::this_thread::sleep_for(2ms);
      }
    }
    return false;
  }

  /// Publishes a 64×36 stereo frame (the calibration's 16:9) with both cameras looking along
  /// the robot's -z (left at x = -0.03 m, right at +0.03 m).
  void publishFrame(link::proto::PoseSource pose_source = link::proto::POSE_SOURCE_JOINT_BUFFER,
                    std::uint64_t calibration_generation = 0, std::int64_t age_ns = 5'000'000) {
    link::proto::StereoFrame f;
    f.set_sequence(++sequence_);
    f.set_calibration_generation(calibration_generation);
    const std::int64_t now = link::linkNowNs();
    f.mutable_stamps()->set_capture_ns(now - age_ns);
    for (int i = 0; i < 2; ++i) {
      auto* image = i == 0 ? f.mutable_left() : f.mutable_right();
      image->set_width(64);
      image->set_height(36);
      image->set_capture_ns(now - age_ns);
      Eigen::Isometry3d T_robot_cam = Eigen::Isometry3d::Identity();
      T_robot_cam.translation().x() = i == 0 ? -0.03 : 0.03;
      link::toLinkPose(T_robot_cam, image->mutable_t_robot_cam());
      image->set_pose_source(pose_source);
    }
    server_->publishStereoFrame(f, jpeg_, jpeg_);
  }

  /// Publishes `state` until the view's link has it (its t_ns): only then does "nothing changed"
  /// after a frame mean anything.
  bool publishUntilArrived(const link::proto::RobotState& state) {
    return ::telesphere::test::eventually([&] {
      server_->publishRobotState(state);
      const auto arrived = view_->client().latestRobotState();
      return arrived && arrived->t_ns() == state.t_ns();
    });
  }

  bool frame(std::int64_t display_ns = 0, std::string* error = nullptr) {
    std::string local;
    return view_->beginFrame(T_vr_hmd_, display_ns ? display_ns : link::linkNowNs() + 11'000'000, true,
                             error ? error : &local);
  }

  /// Displays one frame (begin and end) and says whether it began without error.
  bool shownFrame() {
    const bool ok = frame();
    view_->endFrame(link::linkNowNs(), 1.0, 0);
    return ok;
  }

  /// Left eye into the 32×32 target: RGBA8.
  std::vector<std::uint8_t> renderLeft() {
    std::string error;
    EXPECT_TRUE(view_->renderEye(0, T_vr_hmd_, eye_, target_->framebuffer(), &error)) << error;
    return target_->readRgba8();
  }

  std::vector<link::proto::ControlRequest> requests() {
    std::lock_guard lock(mutex_);
    return requests_;
  }

  std::unique_ptr<gl::EglContext> context_;
  std::unique_ptr<link::LinkServer> server_;
  std::unique_ptr<frame_loop::OperatorView> view_;
  std::unique_ptr<gl::OffscreenTarget> target_;
  render::EyeView eye_;
  Eigen::Isometry3d T_vr_hmd_ = Eigen::Isometry3d::Identity();
  std::uint64_t sequence_ = 0;
  link::SharedBytes jpeg_ = std::make_shared<const std::vector<std::uint8_t>>(test::texturedJpeg(64, 36, 5));
  std::mutex mutex_;
  std::vector<link::proto::ControlRequest> requests_;
  calib::SystemCalibration robot_calibration_;  ///< what get_calibration answers (under mutex_)
  bool calibration_unanswered_ = false;          ///< get_calibration refused (under mutex_)
};

TEST_F(OperatorViewTest, ShowsTheBorderColourUntilTheFirstFrameThenTheCameraImage) {
  std::string error;
  ASSERT_TRUE(frame(0, &error)) << error;
  EXPECT_FALSE(view_->hasImage());
  ASSERT_TRUE(view_->renderEye(0, T_vr_hmd_, eye_, target_->framebuffer(), &error)) << error;
  auto pixels = target_->readRgba8();
  EXPECT_EQ(pixels[0], 0);
  EXPECT_EQ(pixels[2], 255);  // the border colour: blue
  EXPECT_FALSE(view_->T_cam_eye(0, T_vr_hmd_)) << "no eye pose before the first frame";
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return frame() && view_->hasImage();
  }));
  ASSERT_TRUE(view_->renderEye(0, T_vr_hmd_, eye_, target_->framebuffer(), &error)) << error;
  pixels = target_->readRgba8();
  std::size_t blue = 0;
  for (std::size_t i = 0; i < pixels.size(); i += 4) blue += (pixels[i] == 0 && pixels[i + 1] == 0 && pixels[i + 2] == 255);
  EXPECT_LT(blue, pixels.size() / 4 / 2) << "the camera image fills the view";
  // The pose each eye is rendered with: T_robot_cam⁻¹ · T_robot_vr · T_vr_eye, each camera its own.
  Eigen::Isometry3d T_vr_eye = Eigen::Isometry3d::Identity();
  T_vr_eye.translation() << 0.01, -0.02, 0.03;
  for (int eye = 0; eye < 2; ++eye) {
    Eigen::Isometry3d T_robot_cam = Eigen::Isometry3d::Identity();
    T_robot_cam.translation().x() = eye == 0 ? -0.03 : 0.03;
    const auto T_cam_eye = view_->T_cam_eye(eye, T_vr_eye);
    ASSERT_TRUE(T_cam_eye);
    EXPECT_TRUE(T_cam_eye->isApprox(T_robot_cam.inverse() * view_->T_robot_vr() * T_vr_eye, 1e-12)) << eye;
  }
  EXPECT_FALSE(view_->T_cam_eye(2, T_vr_eye));
}

TEST_F(OperatorViewTest, HeadTargetsReachTheRobotWithThePredictedDisplayTime) {
  T_vr_hmd_.translation() << 0.1, 1.6, -0.2;
  const std::int64_t display = link::linkNowNs() + 22'000'000;
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    frame(display);
    const auto t = server_->latestHeadTarget();
    return t && t->predicted_display_ns() == display;
  }));
  const auto target = server_->latestHeadTarget();
  EXPECT_TRUE(target->valid());
  EXPECT_NEAR(link::fromLinkPose(target->t_vr_hmd()).translation().z(), -0.2, 1e-12);
  EXPECT_GE(view_->stats().head_targets_sent, 1u);
}

TEST_F(OperatorViewTest, FollowsTheRobotsModeRadiusAndNominalMappingButNotNonsense) {
  link::proto::RobotState state;
  state.set_visual_mode(link::proto::VISUAL_MODE_ORIENTATION3D);
  state.set_sphere_radius(3.0);
  state.set_nominal_set(true);
  Eigen::Isometry3d T_robot_vr = Eigen::Isometry3d::Identity();
  T_robot_vr.translation() << 0.5, -0.2, 1.0;
  link::toLinkPose(T_robot_vr, state.mutable_t_robot_vr());
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    server_->publishRobotState(state);
    frame();
    return view_->settings().mode == link::VisualMode::kOrientation3d;
  }));
  EXPECT_DOUBLE_EQ(view_->settings().radius, 3.0);
  EXPECT_TRUE(view_->T_robot_vr().isApprox(T_robot_vr));
  EXPECT_TRUE(view_->stats().nominal_from_robot);
  EXPECT_EQ(view_->stats().settings_changes, 1u);

  // Nonsense from the robot changes nothing.
  for (const double radius : {std::nan(""), -1.0, 0.0, std::numeric_limits<double>::infinity()}) {
    state.set_visual_mode(static_cast<link::proto::VisualMode>(17));
    state.set_sphere_radius(radius);
    state.set_t_ns(state.t_ns() + 1);
    ASSERT_TRUE(publishUntilArrived(state));
    frame();
    EXPECT_EQ(view_->settings().mode, link::VisualMode::kOrientation3d) << radius;
    EXPECT_DOUBLE_EQ(view_->settings().radius, 3.0) << radius;
  }
}

/// The robot's end of the link, keeping the XR telemetry it receives.
class XrTelemetryTap final : public link::LinkTap {
 public:
  void onLinkMessage(Direction direction, const link::proto::Envelope& envelope,
                     const std::shared_ptr<const std::vector<std::uint8_t>>&,
                     const std::shared_ptr<const std::vector<std::uint8_t>>&) override {
    if (direction != Direction::kReceived || !envelope.has_xr_telemetry()) return;
    std::lock_guard lock(mutex_);
    latest_ = envelope.xr_telemetry();
  }
  std::optional<link::proto::XrTelemetry> latest() const {
    std::lock_guard lock(mutex_);
    return latest_;
  }

 private:
  mutable std::mutex mutex_;
  std::optional<link::proto::XrTelemetry> latest_;
};

TEST_F(OperatorViewTest, TheSessionsSceneProxyIsFollowedAndTheOperatorsChoiceGoesToTheRobot) {
  const auto tap = std::make_shared<XrTelemetryTap>();
  server_->setTap(tap);
  // No robot state yet: the operator's key changes the proxy here at once.
  ASSERT_EQ(view_->depthProxy(), link::DepthProxy::kFixed);
  view_->cycleDepthProxy();
  EXPECT_EQ(view_->depthProxy(), link::DepthProxy::kRadius);
  EXPECT_TRUE(requests().empty()) << "nothing to ask without a robot";

  // A robot that holds no choice leaves the view's own.
  link::proto::RobotState state;
  state.set_sphere_radius(1.0);
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    server_->publishRobotState(state);
    return frame() && view_->client().latestRobotState();
  }));
  EXPECT_EQ(view_->depthProxy(), link::DepthProxy::kRadius);

  // The session's choice is followed.
  state.set_depth_proxy(link::proto::DEPTH_PROXY_GRID);
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    server_->publishRobotState(state);
    frame();
    return view_->depthProxy() == link::DepthProxy::kGrid;
  }));

  // With a robot, the key asks it (the console and the recording see the choice); the view
  // follows the robot's state, not the key.
  view_->cycleDepthProxy();
  ASSERT_TRUE(::telesphere::test::eventually([&] { return requests().size() == 1; }));
  EXPECT_EQ(requests()[0].set_depth_proxy(), link::proto::DEPTH_PROXY_FIXED);
  frame();
  EXPECT_EQ(view_->depthProxy(), link::DepthProxy::kGrid) << "until the robot says so";
  state.set_depth_proxy(link::proto::DEPTH_PROXY_FIXED);
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    server_->publishRobotState(state);
    frame();
    return view_->depthProxy() == link::DepthProxy::kFixed;
  }));

  // A value this build does not know changes nothing.
  state.set_depth_proxy(static_cast<link::proto::DepthProxyProto>(17));
  state.set_t_ns(state.t_ns() + 1);
  ASSERT_TRUE(publishUntilArrived(state));
  frame();
  EXPECT_EQ(view_->depthProxy(), link::DepthProxy::kFixed);

  // The telemetry says what the eyes are rendered with: the fixed sphere of the session's radius,
  // no estimate yet.
  std::optional<link::proto::XrTelemetry> telemetry;
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    shownFrame();
    telemetry = tap->latest();
    return telemetry && telemetry->has_depth();
  }));
  EXPECT_EQ(telemetry->depth().proxy(), link::proto::DEPTH_PROXY_FIXED);
  ASSERT_EQ(telemetry->depth().radius_m_size(), 2);
  EXPECT_DOUBLE_EQ(telemetry->depth().radius_m(0), 1.0);
  EXPECT_DOUBLE_EQ(telemetry->depth().radius_m(1), 1.0);
  EXPECT_EQ(telemetry->depth().matched_fraction_size(), 0);
  EXPECT_LT(telemetry->depth().estimate_age_ms(), 0.0);
  server_->setTap(nullptr);
}

TEST_F(OperatorViewTest, OperatorRequestsReachTheRobotClampedToItsRange) {
  view_->requestNextMode();            // full6d → orientation3d
  view_->requestRadiusScaled(1.25);    // 1 m → 1.25 m
  view_->requestRadiusScaled(1e9);     // clamped to 1000 m
  view_->requestRadiusScaled(1e-9);    // clamped to 0.05 m
  view_->requestCaptureNominal();
  ASSERT_TRUE(::telesphere::test::eventually([&] { return requests().size() == 5; }));
  const auto r = requests();
  EXPECT_EQ(r[0].set_visual_mode(), link::proto::VISUAL_MODE_ORIENTATION3D);
  EXPECT_DOUBLE_EQ(r[1].set_sphere_radius(), 1.25);
  EXPECT_DOUBLE_EQ(r[2].set_sphere_radius(), 1000.0);
  EXPECT_DOUBLE_EQ(r[3].set_sphere_radius(), 0.05);
  EXPECT_TRUE(r[4].capture_nominal());
  EXPECT_TRUE(::telesphere::test::eventually([&] { return view_->lastControlResult() == "capture_nominal: ok"; }));
}

TEST_F(OperatorViewTest, MeasuresSilenceFromTheRobot) {
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return frame() && view_->hasImage();
  }));
  EXPECT_LT(view_->secondsWithoutNewFrame(), 0.5);
  // The robot goes quiet (frames published before the first one showed may still be decoding:
  // let them arrive and go up first).
  std::this_thread::sleep_for(200ms);
  frame();
  std::this_thread::sleep_for(400ms);
  frame();
  EXPECT_GE(view_->secondsWithoutNewFrame(), 0.4);
  EXPECT_TRUE(view_->hasImage()) << "the last frame stays on screen";
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return frame() && view_->secondsWithoutNewFrame() < 0.1;
  }));
}

// A calibration applied live on the robot (issue #15): the view fetches it when the robot's state
// names a new generation, and renders with it from the first frame the robot stamped with it,
// not before (that frame's pose came from the old one).
TEST_F(OperatorViewTest, TakesTheRobotsCalibrationAtTheFirstFrameStampedWithIt) {
  {
    std::lock_guard lock(mutex_);
    for (auto& camera : robot_calibration_.cameras) {  // a 40 % longer focal length: the image zooms
      Eigen::VectorXd p = camera.camera.params();
      p[0] *= 1.4;
      p[1] *= 1.4;
      camera.camera = *calib::GenericCamera::create(camera.camera.modelName(), p);
    }
  }
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame(link::proto::POSE_SOURCE_JOINT_BUFFER, 1);
    return shownFrame() && view_->hasImage();
  }));
  const auto before = renderLeft();
  EXPECT_EQ(view_->stats().calibration_generation, 0u);

  // The robot now uses generation 2; its frames are still stamped with 1 for a while.
  link::proto::RobotState state;
  state.set_calibration_generation(2);
  bool asked = false;
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    server_->publishRobotState(state);
    publishFrame(link::proto::POSE_SOURCE_JOINT_BUFFER, 1);
    shownFrame();
    for (const auto& r : requests()) asked = asked || r.get_calibration();
    return asked;
  }));
  // The answer is in (fetched, waiting for its first frame); new frames of generation 1 keep the old models.
  ASSERT_TRUE(::telesphere::test::eventually([&] { return view_->calibrationPending(); }));
  for (int i = 0; i < 3; ++i) {
    publishFrame(link::proto::POSE_SOURCE_JOINT_BUFFER, 1);
    ASSERT_TRUE(::telesphere::test::eventually([&] {  // until this very frame is on show
      return shownFrame() && view_->frame()->frame.sequence() == sequence_;
    }));
  }
  EXPECT_EQ(view_->stats().calibration_generation, 0u);
  EXPECT_EQ(renderLeft(), before) << "a frame stamped with the old calibration is shown with it";

  ASSERT_TRUE(::telesphere::test::eventually([&] {
    server_->publishRobotState(state);
    publishFrame(link::proto::POSE_SOURCE_JOINT_BUFFER, 2);
    return shownFrame() && view_->stats().calibration_generation == 2u;
  }));
  EXPECT_EQ(view_->stats().calibration_changes, 1u);
  const auto after = renderLeft();
  std::size_t changed = 0;
  for (std::size_t i = 0; i < after.size(); i += 4) changed += std::abs(int(after[i]) - int(before[i])) > 8;
  EXPECT_GT(changed, after.size() / 4 / 10) << "the new focal length zooms the image";
  std::size_t asks = 0;
  for (const auto& r : requests()) asks += r.get_calibration();
  EXPECT_LE(asks, 2u) << "asked once (again only after 3 s without an answer)";
}

// Issue #30: frames stamped with a new calibration arrive before its models do (the robot did not
// answer get_calibration yet). They are not drawn with the old models: the last frame of the old
// calibration stays until the new one is in.
TEST_F(OperatorViewTest, FramesOfANewCalibrationWaitForItsModels) {
  {
    std::lock_guard lock(mutex_);
    calibration_unanswered_ = true;
    for (auto& camera : robot_calibration_.cameras) {
      Eigen::VectorXd p = camera.camera.params();
      p[0] *= 1.4;
      p[1] *= 1.4;
      camera.camera = *calib::GenericCamera::create(camera.camera.modelName(), p);
    }
  }
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame(link::proto::POSE_SOURCE_JOINT_BUFFER, 1);
    return shownFrame() && view_->hasImage();
  }));
  // Frames of generation 1 still on their way are shown too: the last one sent is the last old one.
  ASSERT_TRUE(::telesphere::test::eventually([&] { return shownFrame() && view_->frame()->frame.sequence() == sequence_; }));
  const std::uint64_t last_old = view_->frame()->frame.sequence();
  const auto before = renderLeft();
  link::proto::RobotState state;
  state.set_calibration_generation(2);
  // Generation 2's frames come; its calibration does not: they are held back, the old frame stays.
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    server_->publishRobotState(state);
    publishFrame(link::proto::POSE_SOURCE_JOINT_BUFFER, 2);
    shownFrame();
    return view_->stats().frames_held_for_calibration >= 3;
  }));
  EXPECT_EQ(view_->frame()->frame.sequence(), last_old);
  EXPECT_EQ(view_->stats().calibration_generation, 0u);
  EXPECT_EQ(renderLeft(), before);
  // The robot answers: the next frame of generation 2 is shown with its own models.
  {
    std::lock_guard lock(mutex_);
    calibration_unanswered_ = false;
  }
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    server_->publishRobotState(state);
    publishFrame(link::proto::POSE_SOURCE_JOINT_BUFFER, 2);
    return shownFrame() && view_->stats().calibration_generation == 2u;
  }, 10000ms));
  EXPECT_EQ(view_->frame()->frame.calibration_generation(), 2u);
  EXPECT_NE(renderLeft(), before);
}

TEST_F(OperatorViewTest, ARestartedRobotCountingFromOneAgainIsShown) {
  const auto shown_frame = [&] {
    const bool ok = frame();
    view_->endFrame(link::linkNowNs(), 1.0, 0);
    return ok;
  };
  sequence_ = 5000;
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return shown_frame() && view_->hasImage();
  }));
  ASSERT_GT(view_->frame()->frame.sequence(), 5000u);
  const auto shown_before = view_->stats().stereo_frames_shown;
  sequence_ = 0;  // telesphere-robot restarted
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return shown_frame() && view_->frame()->frame.sequence() < 5000u;
  })) << "frames of the restarted robot must replace the old ones";
  EXPECT_GT(view_->stats().stereo_frames_shown, shown_before);
}

TEST_F(OperatorViewTest, AnImageOlderThanOneSecondIsShownGreyInARedBorder) {
  // Captured 1.5 s before it is shown (a link that stalled): the operator must see it is old.
  std::string error;
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame(link::proto::POSE_SOURCE_JOINT_BUFFER, 0, 1'500'000'000);
    return frame(0, &error) && view_->hasImage();
  })) << error;
  EXPECT_EQ(view_->settings().image_saturation, 0.0f);
  const auto pixels = renderLeft();
  EXPECT_EQ(pixels[0], 217) << "the red border";
  EXPECT_EQ(pixels[1], 38);
  // Below the "STALE" words (which span this small view's top two thirds), inside the border.
  std::size_t grey = 0, coloured = 0;
  for (int y = 23; y < 30; ++y)
    for (int x = 2; x < 30; ++x) {
      const std::uint8_t* p = &pixels[(static_cast<std::size_t>(y) * 32 + x) * 4];
      if (p[0] == 0 && p[1] == 0 && p[2] == 255) continue;  // the view's blue border colour
      (std::abs(p[0] - p[1]) <= 1 && std::abs(p[2] - p[1]) <= 1 ? grey : coloured) += 1;
    }
  EXPECT_GT(grey, 100u);
  EXPECT_EQ(coloured, 0u);
  view_->endFrame(link::linkNowNs(), 1.0, 0);
  EXPECT_GE(view_->stats().frames_stale, 1u);
  // A fresh frame brings the colour back.
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return frame(0, &error) && view_->settings().image_saturation == 1.0f;
  })) << error;
}

TEST_F(OperatorViewTest, GreyscaleFramesFromAMono8CameraAreShown) {
  jpeg_ = std::make_shared<const std::vector<std::uint8_t>>(
      test::encodeJpeg(test::texturedRgb(64, 36, 5), 64, 36, TJSAMP_GRAY));
  std::string error;
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return frame(0, &error) && view_->hasImage();
  })) << error;
  EXPECT_EQ(view_->frame()->left->subsampling, link::ChromaSubsampling::kGray);
  const auto pixels = renderLeft();
  std::size_t grey = 0;
  for (std::size_t i = 0; i < pixels.size(); i += 4) {
    if (pixels[i] == 0 && pixels[i + 1] == 0 && pixels[i + 2] == 255) continue;  // border
    EXPECT_NEAR(pixels[i], pixels[i + 1], 1);
    EXPECT_NEAR(pixels[i + 2], pixels[i + 1], 1);
    ++grey;
  }
  EXPECT_GT(grey, pixels.size() / 4 / 2);
}

TEST_F(OperatorViewTest, NewFramesComeThroughTheUploadRingAndLookTheSameAsFromDecoderMemory) {
  // The first frame is decoded before the ring knows the images' size: from the decoder's memory.
  std::string error;
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return frame(0, &error) && view_->hasImage();
  })) << error;
  const auto first = view_->frame();
  const bool first_in_ring = first->left->slot != nullptr;
  const auto from_memory = renderLeft();
  // The same image again, now decoded straight into the ring's GL buffer memory.
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return frame(0, &error) && view_->frame()->left->slot && view_->frame()->right->slot;
  })) << error;
  EXPECT_FALSE(first_in_ring) << "the ring was made at the first frame";
  EXPECT_EQ(renderLeft(), from_memory) << "the same pixels either way";
  view_->endFrame(link::linkNowNs(), 1.0, 0);
  const frame_loop::OperatorViewStats stats = view_->stats();
  EXPECT_GE(stats.images_in_upload_slots, 2u);
  EXPECT_GE(stats.images_in_own_memory, 2u);
  EXPECT_GT(stats.decode_ms_p50, 0.0);
}

TEST_F(OperatorViewTest, FramesWithoutAMeasuredPoseAreDimmedOrTheLastMeasuredOneIsHeld) {
  using link::proto::POSE_SOURCE_FIXED_CALIBRATION;
  const auto redGreen = [](const std::vector<std::uint8_t>& rgba) {  // the border has none
    double sum = 0;
    for (std::size_t i = 0; i < rgba.size(); i += 4) sum += rgba[i] + rgba[i + 1];
    return sum;
  };
  // Before any measured frame: an unmeasured one is shown, dimmed.
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame(POSE_SOURCE_FIXED_CALIBRATION);
    return shownFrame() && view_->hasImage();
  }));
  EXPECT_TRUE(view_->showingUnmeasured());
  EXPECT_FLOAT_EQ(view_->settings().image_gain, frame_loop::OperatorView::kUnmeasuredGain);
  const double dimmed = redGreen(renderLeft());
  EXPECT_GE(view_->stats().unmeasured_frames_shown, 1u);

  // Measured frames: full brightness, the same picture.
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame();
    return shownFrame() && !view_->showingUnmeasured();
  }));
  EXPECT_FLOAT_EQ(view_->settings().image_gain, 1.0f);
  const double bright = redGreen(renderLeft());
  EXPECT_NEAR(dimmed / bright, frame_loop::OperatorView::kUnmeasuredGain, 0.02);

  // Unmeasured frames again: the measured frame stays on show for hold_measured_s (0.3 s here),
  // then they are shown, dimmed.
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(::telesphere::test::eventually([&] {
    publishFrame(POSE_SOURCE_FIXED_CALIBRATION);
    shownFrame();
    if (!view_->showingUnmeasured()) {  // a measured frame stays on show
      EXPECT_EQ(view_->frame()->frame.left().pose_source(), link::proto::POSE_SOURCE_JOINT_BUFFER);
    }
    return view_->showingUnmeasured();
  }));
  EXPECT_GE(std::chrono::steady_clock::now() - start, 300ms);
  EXPECT_EQ(view_->frame()->frame.left().pose_source(), POSE_SOURCE_FIXED_CALIBRATION);
  EXPECT_GE(view_->stats().unmeasured_frames_held_back, 1u);
}

TEST_F(OperatorViewTest, WithTheDepthHoldEachNewImageIsShownWithTheDepthOfItsOwnPair) {
  // The grid proxy. Without the hold a new image is shown at once, with the depth the worker had:
  // the pair before's. With it the image waits, the one on show staying, until its own pair's depth
  // is in; with a hold too short for a sweep it is shown when the wait runs out, never later.
  // Counted over six images after the worker's first estimate (its first sweep builds the sample
  // tables, seconds under the sanitizers).
  struct Run {
    double hold_ms;
    std::uint64_t shown = 0, own = 0, held = 0, timeouts = 0;
  };
  std::vector<Run> runs = {{0.0}, {3000.0}, {1e-3}};
  for (Run& run : runs) {
    makeView([&](frame_loop::OperatorViewOptions& o) {
      o.depth_proxy = link::DepthProxy::kGrid;
      o.depth_hold_ms = run.hold_ms;
    });
    ASSERT_TRUE(::telesphere::test::eventually([&] { return showNextFrame() && view_->stats().depth_estimates > 0; }, 60s))
        << "hold " << run.hold_ms << " ms: no depth estimate";
    const frame_loop::OperatorViewStats before = view_->stats();
    for (int i = 0; i < 6; ++i) ASSERT_TRUE(showNextFrame()) << "hold " << run.hold_ms << " ms, frame " << i;
    const frame_loop::OperatorViewStats after = view_->stats();
    run.shown = after.stereo_frames_shown - before.stereo_frames_shown;
    run.own = after.depth_images_with_own_depth - before.depth_images_with_own_depth;
    run.held = after.depth_images_held - before.depth_images_held;
    run.timeouts = after.depth_hold_timeouts - before.depth_hold_timeouts;
    std::printf("hold %g ms: %llu images shown, %llu with their own depth at once, %llu held (wait p50 %.1f ms), %llu "
                "timeouts\n",
                run.hold_ms, static_cast<unsigned long long>(run.shown), static_cast<unsigned long long>(run.own),
                static_cast<unsigned long long>(run.held), after.depth_hold_ms_p50,
                static_cast<unsigned long long>(run.timeouts));
  }
  EXPECT_LE(runs[0].own, 1u);  // the sweep starts as the image is shown
  EXPECT_EQ(runs[0].held + runs[0].timeouts, 0u);
  EXPECT_GE(runs[1].shown, 6u);
  EXPECT_EQ(runs[1].own, runs[1].shown);  // every image waited for its own depth
  EXPECT_EQ(runs[1].held, runs[1].shown);
  EXPECT_EQ(runs[1].timeouts, 0u);
  EXPECT_GE(runs[2].timeouts, 5u);
  EXPECT_LE(runs[2].own, 1u);
}

TEST_F(OperatorViewTest, OnTheMediaPathTheZeroMqLinkCarriesNoFrames) {
  // Over the Internet both links share the operator's downlink: a TCP copy of every frame would
  // take the rate the media path adapts to (and queue behind it for seconds).
  view_.reset();
  frame_loop::OperatorViewOptions options;
  options.endpoints = operatorViewEndpoints();
  options.media_link = true;
  options.media_port = 27389;  // nobody sends there: only the ZeroMQ link could bring frames
  view_ = std::make_unique<frame_loop::OperatorView>(robot_calibration_, options);
  ASSERT_TRUE(telesphere::test::eventually([&] {
    shownFrame();
    return server_->stats().received > 0;  // the view's link is up (its pings arrive)
  }, 5000ms));
  for (int i = 0; i < 10; ++i) {
    publishFrame();
    shownFrame();
    std::this_thread::sleep_for(20ms);
  }
  std::this_thread::sleep_for(200ms);
  EXPECT_FALSE(view_->client().takeLatestFrame()) << "the ZeroMQ link subscribed to frames beside the media path";
}

TEST(TrialIndicator, FillAtTheExtremes) {
  EXPECT_EQ(frame_loop::trialIndicatorFill(0.0, 300.0), 0.0);
  EXPECT_EQ(frame_loop::trialIndicatorFill(-5.0, 300.0), 0.0);  // a clock that stepped back shows nothing
  EXPECT_EQ(frame_loop::trialIndicatorFill(std::nan(""), 300.0), 0.0);
  EXPECT_DOUBLE_EQ(frame_loop::trialIndicatorFill(150.0, 300.0), 0.5);
  EXPECT_EQ(frame_loop::trialIndicatorFill(1e9, 300.0), 1.0);  // past the limit: full (and red)
  EXPECT_DOUBLE_EQ(frame_loop::trialIndicatorFill(90.0, 0.0), 0.5);  // no limit: one sweep a minute
  EXPECT_NEAR(frame_loop::trialIndicatorFill(1e-9, 1e-12), 1.0, 0.0);
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{96, 96}, std::pair{2064, 2208}}) {
    const frame_loop::TrialIndicatorGeometry g = frame_loop::trialIndicatorGeometry(w, h);
    EXPECT_GE(g.width, 8);
    EXPECT_GE(g.height, 3);
    if (w >= 96) {  // inside the image, centred, small
      EXPECT_GE(g.x, 0);
      EXPECT_LE(g.x + g.width, w);
      EXPECT_NEAR(g.x + g.width / 2.0, w / 2.0, 1.0);
      EXPECT_LE(g.width * g.height, w * h / 100);
    }
  }
}

TEST(TrialIndicator, DrawsTheElapsedShareAndLeavesTheRestOfTheImage) {
  std::string error;
  auto context = gl::EglContext::createSurfaceless(&error);
  ASSERT_TRUE(context) << error;
  const int w = 400, h = 300;
  gl::OffscreenTarget target(w, h);
  const auto draw = [&](double elapsed_s, double limit_s) {
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
    glViewport(0, 0, w, h);
    glClearColor(0.0f, 0.0f, 1.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    frame_loop::drawTrialIndicator(target.framebuffer(), w, h, elapsed_s, limit_s);
    EXPECT_FALSE(glIsEnabled(GL_SCISSOR_TEST));  // no state left behind
    return target.readRgba8();
  };
  const frame_loop::TrialIndicatorGeometry g = frame_loop::trialIndicatorGeometry(w, h);
  const int row = h - 1 - (g.y + g.height / 2);  // image rows from the top
  const auto at = [&](const std::vector<std::uint8_t>& p, int x, int y) {
    return std::array<int, 3>{p[std::size_t((y * w + x) * 4)], p[std::size_t((y * w + x) * 4 + 1)],
                              p[std::size_t((y * w + x) * 4 + 2)]};
  };
  const auto near = [](const std::array<int, 3>& a, const std::array<int, 3>& b) {  // ±1 of 8-bit rounding
    for (int i = 0; i < 3; ++i)
      if (std::abs(a[std::size_t(i)] - b[std::size_t(i)]) > 1) {
        ADD_FAILURE() << a[0] << "," << a[1] << "," << a[2] << " vs " << b[0] << "," << b[1] << "," << b[2];
        return false;
      }
    return true;
  };
  auto p = draw(100.0, 300.0);  // a third of 5 minutes
  EXPECT_TRUE(near(at(p, g.x + g.width / 6, row), {51, 191, 77}));    // green, filled
  EXPECT_TRUE(near(at(p, g.x + g.width / 2, row), {64, 64, 64}));     // grey, to come
  EXPECT_TRUE(near(at(p, g.x + g.width / 5, row), {13, 13, 13}));     // the 1-minute gap
  EXPECT_TRUE(near(at(p, 5, 5), {0, 0, 255}));                        // the eye image
  EXPECT_TRUE(near(at(p, g.x + g.width / 2, row - g.height), {0, 0, 255}));
  p = draw(270.0, 300.0);  // the last minute: amber
  EXPECT_TRUE(near(at(p, g.x + g.width / 6, row), {242, 166, 26}));
  p = draw(301.0, 300.0);  // past the limit: red, full
  EXPECT_TRUE(near(at(p, g.x + g.width - 2, row), {217, 38, 26}));
}

}  // namespace
}  // namespace telesphere::xr
