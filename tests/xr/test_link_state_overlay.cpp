// SPDX-License-Identifier: MIT
/// @brief The link's cues in the operator's view (xr/frame_loop/link_state_overlay.h) on a real GL
///        context: nothing drawn while all is well; an amber border after 250 ms, a red one and
///        "STALE" after 1 s; the stream's settings while below nominal; "ROBOT BEHIND YOU". Each
///        state is written as a PNG (build/test-out/link_state/) to be looked at. Also the font.
#include <gtest/gtest.h>

#include <filesystem>

#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "shaders/png_io.h"
#include "xr/frame_loop/hud_text.h"
#include "xr/frame_loop/link_state_overlay.h"

namespace telesphere::xr {
namespace {

constexpr int kW = 480, kH = 528;  // one eye, a third of a headset's

class LinkStateOverlay : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    context_ = gl::EglContext::createSurfaceless(&error);
    ASSERT_TRUE(context_) << error;
    target_ = std::make_unique<gl::OffscreenTarget>(kW, kH);
  }

  /// A blue-green "camera image", the cues of `state` over it; the pixels, top row first.
  std::vector<std::uint8_t> draw(const frame_loop::LinkState& state, const std::string& png) {
    target_->clear(0.2f, 0.45f, 0.5f, 1.0f);
    frame_loop::drawLinkState(target_->framebuffer(), kW, kH, state, {});
    auto pixels = target_->readRgba8();
    const std::string dir = std::string(TELESPHERE_BINARY_DIR) + "/test-out/link_state";
    std::filesystem::create_directories(dir);
    std::string error;
    EXPECT_TRUE(gl::writePng(dir + "/" + png, kW, kH, 4, pixels.data(), &error)) << error;
    return pixels;
  }
  static const std::uint8_t* at(const std::vector<std::uint8_t>& p, int x, int y_from_top) {
    return &p[(static_cast<std::size_t>(y_from_top) * kW + x) * 4];
  }
  static int countColour(const std::vector<std::uint8_t>& p, int r, int g, int b, int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const auto* q = at(p, x, y);
        n += std::abs(q[0] - r) <= 2 && std::abs(q[1] - g) <= 2 && std::abs(q[2] - b) <= 2;
      }
    return n;
  }

  std::unique_ptr<gl::EglContext> context_;
  std::unique_ptr<gl::OffscreenTarget> target_;
};

constexpr int kImageR = 51, kImageG = 115, kImageB = 128;  // the clear colour as bytes

TEST_F(LinkStateOverlay, AFreshImageAtNominalSettingsGetsNothing) {
  frame_loop::LinkState state;
  state.image_age_ms = 120;
  state.eye_camera_distance_m = 0.05;
  const auto p = draw(state, "fresh.png");
  EXPECT_EQ(countColour(p, kImageR, kImageG, kImageB, 0, 0, kW, kH), kW * kH);
}

TEST_F(LinkStateOverlay, After250msTheBorderTurnsAmberAfter1sRedWithStale) {
  frame_loop::LinkState state;
  state.image_age_ms = 400;
  auto p = draw(state, "tinted_400ms.png");
  const int t = kW / 60;
  EXPECT_EQ(countColour(p, 242, 153, 26, 0, 0, kW, t), kW * t) << "the top strip";
  EXPECT_EQ(countColour(p, 242, 153, 26, 0, 0, t, kH), t * kH) << "the left strip";
  EXPECT_EQ(countColour(p, kImageR, kImageG, kImageB, t, t, kW - t, kH - t), (kW - 2 * t) * (kH - 2 * t))
      << "the image itself untouched";
  state.image_age_ms = 1500;
  p = draw(state, "stale_1500ms.png");
  EXPECT_EQ(countColour(p, 217, 38, 26, 0, kH - t, kW, kH), kW * t) << "the bottom strip, red";
  // "STALE 1.5S" in red near the top, centred.
  EXPECT_GT(countColour(p, 242, 51, 38, kW / 4, t, 3 * kW / 4, kH / 5), 100);
  EXPECT_EQ(frame_loop::stalenessOf(249.9, {}), frame_loop::Staleness::kFresh);
  EXPECT_EQ(frame_loop::stalenessOf(250, {}), frame_loop::Staleness::kTinted);
  EXPECT_EQ(frame_loop::stalenessOf(1000, {}), frame_loop::Staleness::kStale);
  EXPECT_EQ(frame_loop::stalenessOf(-1, {}), frame_loop::Staleness::kFresh) << "no image yet";
  EXPECT_EQ(frame_loop::imageSaturationFor(999, {}), 1.0f);
  EXPECT_EQ(frame_loop::imageSaturationFor(1000, {}), 0.0f);
}

TEST_F(LinkStateOverlay, AStreamBelowNominalSaysWhatItRunsAt) {
  link::proto::StreamState stream;
  stream.set_adapted(true);
  stream.set_fps(15);
  stream.set_scale(0.5);
  stream.set_quality(70);
  stream.set_target_mbit(8.46);
  EXPECT_EQ(frame_loop::streamText(stream), "LINK 8.5M 15HZ 50% Q70");
  stream.set_adapted(false);
  EXPECT_EQ(frame_loop::streamText(stream), "") << "nominal: nothing to say";
  stream.set_adapted(true);
  frame_loop::LinkState state;
  state.image_age_ms = 100;
  state.stream_text = frame_loop::streamText(stream);
  const auto p = draw(state, "stream_below_nominal.png");
  // Light grey glyph pixels around 16 % of the height from the bottom.
  const int y = kH - static_cast<int>(0.16 * kH);
  EXPECT_GT(countColour(p, 217, 217, 217, 0, y - 20, kW, y + 5), 50);
}

TEST_F(LinkStateOverlay, TheRobotBehindIsSaid) {
  frame_loop::LinkState state;
  state.image_age_ms = 100;
  state.eye_camera_distance_m = 0.3;
  const auto p = draw(state, "robot_behind.png");
  EXPECT_GT(countColour(p, 242, 166, 26, 0, kH / 2, kW, kH), 100) << "amber words in the lower half";
  state.eye_camera_distance_m = 0.1;
  EXPECT_FALSE(frame_loop::robotBehind(state, {}));
  state.eye_camera_distance_m = -1;
  EXPECT_FALSE(frame_loop::robotBehind(state, {})) << "unknown is not behind";
}

TEST_F(LinkStateOverlay, AnInsecureLinkIsSaidInRedOnEveryFrame) {
  frame_loop::LinkState state;
  state.image_age_ms = 100;  // fresh, nominal: only the warning
  state.insecure = true;
  const auto p = draw(state, "insecure_link.png");
  // Red glyph pixels around 12 % of the height from the bottom, centred.
  const int y = kH - static_cast<int>(0.12 * kH);
  EXPECT_GT(countColour(p, 242, 38, 26, kW / 4, y - 20, 3 * kW / 4, y + 5), 50);
  EXPECT_EQ(countColour(p, kImageR, kImageG, kImageB, 0, 0, kW, kH / 2), kW * (kH / 2)) << "nothing else drawn";
  state.insecure = false;
  const auto q = draw(state, "secure_link.png");
  EXPECT_EQ(countColour(q, kImageR, kImageG, kImageB, 0, 0, kW, kH), kW * kH);
}

TEST(HudText, GlyphsAndWidths) {
  EXPECT_EQ(frame_loop::glyphOf('0'), frame_loop::glyphOf('0'));
  EXPECT_NE(frame_loop::glyphOf('O'), frame_loop::glyphOf('0'));
  EXPECT_EQ(frame_loop::glyphOf('s'), frame_loop::glyphOf('S')) << "lower case drawn as upper case";
  EXPECT_EQ(frame_loop::glyphOf('~'), (std::array<std::uint8_t, 7>{0x1F, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1F}));
  EXPECT_EQ(frame_loop::hudTextWidth("", 3), 0);
  EXPECT_EQ(frame_loop::hudTextWidth("A", 2), 10);
  EXPECT_EQ(frame_loop::hudTextWidth("AB", 2), 22);
}

}  // namespace
}  // namespace telesphere::xr
