// SPDX-License-Identifier: MIT
/// @brief The clock-paced output on a simulated FrameClock (what the offline replay runs on), on a
///        real EGL context: display frames fall exactly one period apart from the first start,
///        the head is sampled at each display time, the eyes ipd apart; work that overruns a
///        period skips refreshes (the next frame starts at the refresh after the work ended, never
///        a burst) and the loop counts them as missed — all without sleeping.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "shaders/egl_context.h"
#include "xr/frame_loop/operator_loop.h"
#include "xr/frame_loop/paced_output.h"

namespace telesphere::xr {
namespace {

class NullScene final : public frame_loop::OperatorScene {
 public:
  std::vector<std::int64_t> display_ns, shown_ns;
  std::vector<double> head_x;
  bool beginFrame(const Eigen::Isometry3d& T_vr_hmd, std::int64_t display, bool, std::string*) override {
    display_ns.push_back(display);
    head_x.push_back(T_vr_hmd.translation().x());
    return true;
  }
  bool renderEye(int, const Eigen::Isometry3d&, const render::EyeView&, GLuint, std::string*) override { return true; }
  void endFrame(std::int64_t shown, double, std::uint64_t) override { shown_ns.push_back(shown); }
  std::optional<Eigen::Isometry3d> T_cam_eye(int, const Eigen::Isometry3d&) const override { return std::nullopt; }
};

TEST(PacedOutput, OnASimulatedClockFramesFallExactlyOnePeriodApartAndOverrunsSkipRefreshes) {
  std::string error;
  auto context = gl::EglContext::createSurfaceless(&error);
  ASSERT_TRUE(context && context->makeCurrent()) << error;
  constexpr std::int64_t kStart = 5'000'000'000, kPeriod = 10'000'000;  // 100 Hz
  frame_loop::SimulatedFrameClock clock(kStart);
  frame_loop::PacedOutputOptions options;
  options.rate_hz = 100.0;
  options.eye_width = 8;
  options.eye_height = 8;
  options.ipd = 0.06;
  frame_loop::OffscreenOutput output(options, [](double display_s) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().x() = display_s;  // the head's x is the time it was sampled for
    return T;
  }, &clock);
  ASSERT_TRUE(output.complete());
  EXPECT_EQ(output.periodNs(), kPeriod);
  EXPECT_DOUBLE_EQ(output.T_hmd_eye(0).translation().x(), -0.03);
  EXPECT_DOUBLE_EQ(output.T_hmd_eye(1).translation().x(), 0.03);
  NullScene scene;
  frame_loop::OperatorLoop loop(scene, output);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(loop.step(&error)) << error;
  EXPECT_EQ(output.nextStartNs(), kStart + 3 * kPeriod);
  // The fourth frame's work takes 2.5 periods: it is shown when done, the next starts at the
  // refresh after that, and the two refreshes in between are missed.
  clock.sleepUntilNs(kStart + 3 * kPeriod);
  class SlowScene final : public frame_loop::OperatorScene {
   public:
    SlowScene(frame_loop::OperatorScene& inner, frame_loop::SimulatedFrameClock& clock) : inner_(inner), clock_(clock) {}
    bool beginFrame(const Eigen::Isometry3d& T, std::int64_t d, bool v, std::string* e) override {
      clock_.sleepUntilNs(clock_.nowNs() + 25'000'000);
      return inner_.beginFrame(T, d, v, e);
    }
    bool renderEye(int eye, const Eigen::Isometry3d& T, const render::EyeView& view, GLuint fb, std::string* e) override {
      return inner_.renderEye(eye, T, view, fb, e);
    }
    void endFrame(std::int64_t s, double r, std::uint64_t m) override { inner_.endFrame(s, r, m); }
    std::optional<Eigen::Isometry3d> T_cam_eye(int, const Eigen::Isometry3d&) const override { return std::nullopt; }

   private:
    frame_loop::OperatorScene& inner_;
    frame_loop::SimulatedFrameClock& clock_;
  } slow(scene, clock);
  frame_loop::OperatorLoop slow_loop(slow, output);
  ASSERT_TRUE(slow_loop.step(&error)) << error;
  EXPECT_EQ(scene.shown_ns.back(), kStart + 3 * kPeriod + 25'000'000);  // later than its display time
  EXPECT_EQ(output.nextStartNs(), kStart + 6 * kPeriod);
  ASSERT_TRUE(slow_loop.step(&error)) << error;
  EXPECT_EQ(slow_loop.stats().missed_frames, 2u);

  const std::vector<std::int64_t> display = {kStart + 1 * kPeriod, kStart + 2 * kPeriod, kStart + 3 * kPeriod,
                                             kStart + 4 * kPeriod, kStart + 7 * kPeriod};
  EXPECT_EQ(scene.display_ns, display);
  for (std::size_t i = 0; i < display.size(); ++i)
    EXPECT_DOUBLE_EQ(scene.head_x[i], double(display[i] - kStart) * 1e-9) << "frame " << i;
  EXPECT_EQ(clock.nowNs(), kStart + 6 * kPeriod + 25'000'000);  // waited only for what was due
}

}  // namespace
}  // namespace telesphere::xr
