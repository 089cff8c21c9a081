// SPDX-License-Identifier: MIT
/// @brief The one operator frame loop over its seam, with a scripted output (display times and
///        eye draws as a runtime or clock would give them) and a recording scene: every eye is
///        drawn once, after one beginFrame with the frame's head pose and display time; frames
///        the output did not draw reach no endFrame; skipped refreshes are counted from the
///        output's display times (rounded to whole periods), never across an output restart; a
///        failing eye stops the loop with its reason. And skippedPeriods at its edges.
#include <gtest/gtest.h>

#include <deque>
#include <vector>

#include "xr/frame_loop/operator_loop.h"

namespace telesphere::xr {
namespace {

/// One scripted display frame: its refresh time and whether it gets drawn.
struct Scripted {
  std::int64_t refresh_ns;
  bool draw = true;
  bool began = true;
};

class ScriptedOutput final : public frame_loop::OperatorOutput {
 public:
  static constexpr std::int64_t kPeriodNs = 10'000'000;
  std::deque<Scripted> script;
  bool frame(const frame_loop::DrawEye& draw, Shown* shown, std::string*) override {
    const Scripted s = script.front();
    script.pop_front();
    shown->began = s.began;
    if (!s.began) return true;
    frame_loop::DisplayFrame& f = shown->frame;
    f.index = index_++;
    f.refresh_ns = s.refresh_ns;
    f.display_ns = s.refresh_ns + 1'000'000'000;  // another clock: only refresh_ns counts for misses
    f.display_period_ns = kPeriodNs;
    f.T_vr_hmd.translation().x() = double(f.index);
    for (int eye = 0; eye < 2; ++eye) f.T_vr_eye[std::size_t(eye)].translation().x() = double(f.index) + 0.1 * eye;
    if (s.draw) {
      if (!draw(f, 0, 100) || !draw(f, 1, 200)) return false;
      shown->drawn = true;
      shown->shown_ns = f.display_ns;
    }
    return true;
  }

 private:
  std::uint64_t index_ = 0;
};

class RecordingScene final : public frame_loop::OperatorScene {
 public:
  std::vector<std::string> calls;
  std::vector<std::uint64_t> missed_at_end;
  bool fail_right_eye = false;
  bool beginFrame(const Eigen::Isometry3d& T_vr_hmd, std::int64_t display_ns, bool, std::string*) override {
    calls.push_back("begin " + std::to_string(int(T_vr_hmd.translation().x())) + " " + std::to_string(display_ns));
    return true;
  }
  bool renderEye(int eye, const Eigen::Isometry3d& T_vr_eye, const render::EyeView&, GLuint framebuffer,
                 std::string* error) override {
    if (eye == 1 && fail_right_eye) {
      *error = "right eye failed";
      return false;
    }
    calls.push_back("eye " + std::to_string(eye) + " fb " + std::to_string(framebuffer) + " x " +
                    std::to_string(int(std::lround(T_vr_eye.translation().x() * 10))));
    return true;
  }
  void endFrame(std::int64_t shown_ns, double render_ms, std::uint64_t missed) override {
    EXPECT_GT(render_ms, 0.0);  // measured around the eyes (0: not measured at all)
    calls.push_back("end " + std::to_string(shown_ns));
    missed_at_end.push_back(missed);
  }
  std::optional<Eigen::Isometry3d> T_cam_eye(int, const Eigen::Isometry3d&) const override { return std::nullopt; }
};

constexpr std::int64_t P = ScriptedOutput::kPeriodNs;

TEST(OperatorLoop, DrawsBothEyesAfterOneBeginAndEndsOnlyDrawnFrames) {
  ScriptedOutput output;
  RecordingScene scene;
  frame_loop::OperatorLoop loop(scene, output);
  output.script = {{1 * P}, {2 * P, false}, {3 * P}, {0, true, false}};
  std::string error;
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(loop.step(&error)) << error;
  const std::string d0 = std::to_string(1 * P + 1'000'000'000), d2 = std::to_string(3 * P + 1'000'000'000);
  EXPECT_EQ(scene.calls, (std::vector<std::string>{"begin 0 " + d0, "eye 0 fb 100 x 0", "eye 1 fb 200 x 1", "end " + d0,
                                                   "begin 2 " + d2, "eye 0 fb 100 x 20", "eye 1 fb 200 x 21",
                                                   "end " + d2}));
  EXPECT_EQ(loop.stats().frames, 2u);
  EXPECT_EQ(loop.stats().missed_frames, 0u) << "an undrawn frame is a refresh that was waited for, not skipped";
  EXPECT_FALSE(loop.last().began);
}

TEST(OperatorLoop, CountsSkippedRefreshesFromTheOutputsDisplayTimesButNotAcrossARestart) {
  ScriptedOutput output;
  RecordingScene scene;
  frame_loop::OperatorLoop loop(scene, output);
  // 1 → 2: next refresh; 2 → 4: one skipped; 4 → 4.4: rounds to the same period (none);
  // 4.4 → 10: five skipped (5.6 periods round to 6).
  output.script = {{1 * P}, {2 * P}, {4 * P}, {44 * P / 10}, {10 * P}};
  std::string error;
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(loop.step(&error)) << error;
  EXPECT_EQ(scene.missed_at_end, (std::vector<std::uint64_t>{0, 0, 1, 1, 6}));
  EXPECT_EQ(loop.stats().missed_frames, 6u);
  // A new session's clock: a large jump (or one backwards) is not a miss.
  loop.outputRestarted();
  output.script = {{5 * P}, {6 * P}};
  for (int i = 0; i < 2; ++i) ASSERT_TRUE(loop.step(&error)) << error;
  EXPECT_EQ(loop.stats().missed_frames, 6u);
  EXPECT_EQ(loop.stats().frames, 7u);
}

TEST(OperatorLoop, AFailingEyeStopsWithItsReasonAndEndsNothing) {
  ScriptedOutput output;
  RecordingScene scene;
  scene.fail_right_eye = true;
  frame_loop::OperatorLoop loop(scene, output);
  output.script = {{P}};
  std::string error;
  EXPECT_FALSE(loop.step(&error));
  EXPECT_EQ(error, "right eye failed");
  EXPECT_TRUE(scene.missed_at_end.empty());
  EXPECT_EQ(loop.stats().frames, 0u);
}

TEST(SkippedPeriods, AtItsEdges) {
  EXPECT_EQ(frame_loop::skippedPeriods(0, 5 * P, P), 0u) << "no previous frame";
  EXPECT_EQ(frame_loop::skippedPeriods(5 * P, 6 * P, 0), 0u) << "unknown period";
  EXPECT_EQ(frame_loop::skippedPeriods(5 * P, 6 * P, -P), 0u);
  EXPECT_EQ(frame_loop::skippedPeriods(6 * P, 5 * P, P), 0u) << "time going backwards";
  EXPECT_EQ(frame_loop::skippedPeriods(5 * P, 5 * P, P), 0u);
  EXPECT_EQ(frame_loop::skippedPeriods(P, P + P * 3 / 2 - 1, P), 0u) << "1.5 periods round down";
  EXPECT_EQ(frame_loop::skippedPeriods(P, P + P * 3 / 2, P), 1u) << "… and up from there";
  EXPECT_EQ(frame_loop::skippedPeriods(1, std::int64_t(1) << 62, 1), (std::uint64_t(1) << 62) - 2u) << "huge gaps do not overflow";
}

}  // namespace
}  // namespace telesphere::xr
