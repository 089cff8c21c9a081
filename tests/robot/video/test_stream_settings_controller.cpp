// SPDX-License-Identifier: MIT
/// @brief StreamSettingsController: the order of sacrifice (frame rate to 15 Hz, scale, quality,
///        frame rate below 15 Hz) at exact rates, the scale's hysteresis and hold, the bits per
///        pixel learnt from encoded frames, and the extremes of the target rate.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "robot/video/stream_settings_controller.h"

namespace telesphere::robot::video {
namespace {

constexpr std::int64_t kSecondNs = 1'000'000'000;

/// 2×1080p at 1 bit per pixel at q90: 4 147 200 bits per stereo frame at full scale.
StreamSettingsLimits limits1080p() {
  StreamSettingsLimits limits;
  limits.pixels_per_frame = 2.0 * 1920 * 1080;
  limits.initial_bits_per_pixel_q90 = 1.0;
  return limits;
}
constexpr double kFullFrameBits = 2.0 * 1920 * 1080;

TEST(StreamSettingsController, EnoughRateKeepsEverythingNominal) {
  StreamSettingsController controller(limits1080p());
  const StreamSettings s = controller.decide(200e6, 0);  // 45 Hz needs 186.6 Mbit/s
  EXPECT_EQ(s.fps, 45);
  EXPECT_EQ(s.scale, 1.0);
  EXPECT_EQ(s.quality, 90);
  EXPECT_EQ(s.limited_by, StreamLimitedBy::kNothing);
  EXPECT_NEAR(s.predicted_bits_per_s, 45 * kFullFrameBits, 1e-3);
}

TEST(StreamSettingsController, FrameRateGoesFirstDownTo15Hz) {
  StreamSettingsController controller(limits1080p());
  const StreamSettings s = controller.decide(100e6, 0);
  EXPECT_NEAR(s.fps, 100e6 / kFullFrameBits, 1e-9);  // 24.1 Hz
  EXPECT_EQ(s.scale, 1.0);
  EXPECT_EQ(s.quality, 90);
  EXPECT_EQ(s.limited_by, StreamLimitedBy::kFrameRate);
  // Exactly 15 Hz at full scale still fits.
  EXPECT_EQ(controller.decide(15 * kFullFrameBits, 0).scale, 1.0);
}

TEST(StreamSettingsController, ThenTheScaleWithSpareRateInFrameRate) {
  StreamSettingsController controller(limits1080p());
  // 15 Hz at full scale needs 62.2 Mbit/s; at 0.75 a frame is 2.33 Mbit.
  const StreamSettings s = controller.decide(60e6, 0);
  EXPECT_EQ(s.scale, 0.75);
  EXPECT_EQ(s.quality, 90);
  EXPECT_NEAR(s.fps, 60e6 / (kFullFrameBits * 0.5625), 1e-9);  // 25.7 Hz
  EXPECT_EQ(s.limited_by, StreamLimitedBy::kScale);
  // Several steps in one decision when the rate falls far: 0.5 needs 15.6, 0.35 needs 7.6 Mbit/s.
  StreamSettingsController far(limits1080p());
  const StreamSettings t = far.decide(10e6, 0);
  EXPECT_EQ(t.scale, 0.35);
  EXPECT_EQ(far.stats().scale_downs, 3u);
}

TEST(StreamSettingsController, ThenQualityAtTheSmallestScale) {
  StreamSettingsController controller(limits1080p());
  // At 0.35 and 15 Hz, 3 Mbit/s leaves 0.394 of q90's size: between q50 (0.373) and q60 (0.413).
  const StreamSettings s = controller.decide(3e6, 0);
  EXPECT_EQ(s.scale, 0.35);
  EXPECT_EQ(s.fps, 15);
  EXPECT_EQ(s.quality, 55);
  EXPECT_EQ(s.limited_by, StreamLimitedBy::kQuality);
  EXPECT_LE(s.predicted_bits_per_s, 3e6);
  EXPECT_GT(controller.bitsPerFrame(0.35, 56) * 15, 3e6);  // the next quality up would not fit
}

TEST(StreamSettingsController, LastTheFrameRateBelow15HzDownToItsMinimum) {
  StreamSettingsController controller(limits1080p());
  const double floor_frame_bits = kFullFrameBits * 0.35 * 0.35 * 0.373;  // 0.19 Mbit
  const StreamSettings s = controller.decide(1e6, 0);
  EXPECT_EQ(s.quality, 50);
  EXPECT_NEAR(s.fps, 1e6 / floor_frame_bits, 1e-9);  // 5.3 Hz
  EXPECT_EQ(s.limited_by, StreamLimitedBy::kFrameRateBelowFloor);
  EXPECT_EQ(controller.stats().over_budget, 0u);
  // Below what 5 Hz at the floor needs: 5 Hz, counted as over budget.
  const StreamSettings t = controller.decide(0.1e6, 0);
  EXPECT_EQ(t.fps, 5);
  EXPECT_EQ(controller.stats().over_budget, 1u);
}

TEST(StreamSettingsController, TheScaleComesBackWithMarginAndAfterItsHold) {
  StreamSettingsController controller(limits1080p());
  ASSERT_EQ(controller.decide(60e6, 0).scale, 0.75);
  // Enough for full scale at 15 Hz (62.2 Mbit/s) but not 1.25 times it (77.8): stays, and the
  // spare rate goes into frame rate.
  const StreamSettings within = controller.decide(70e6, 10 * kSecondNs);
  EXPECT_EQ(within.scale, 0.75);
  EXPECT_NEAR(within.fps, 70e6 / (kFullFrameBits * 0.5625), 1e-9);
  // With the margin, but 1 s after the step down: stays.
  EXPECT_EQ(controller.decide(80e6, 1 * kSecondNs).scale, 0.75);
  // After the 2 s hold: back to full scale.
  const StreamSettings back = controller.decide(80e6, 2 * kSecondNs);
  EXPECT_EQ(back.scale, 1.0);
  EXPECT_NEAR(back.fps, 80e6 / kFullFrameBits, 1e-9);
  EXPECT_EQ(controller.stats().scale_ups, 1u);
  // Down again at once, hold or not.
  EXPECT_EQ(controller.decide(60e6, 2 * kSecondNs + 1).scale, 0.75);
}

TEST(StreamSettingsController, OneStepUpPerHold) {
  StreamSettingsController controller(limits1080p());
  ASSERT_EQ(controller.decide(3e6, 0).scale, 0.35);
  EXPECT_EQ(controller.decide(1e9, 2 * kSecondNs).scale, 0.5);
  EXPECT_EQ(controller.decide(1e9, 3 * kSecondNs).scale, 0.5);
  EXPECT_EQ(controller.decide(1e9, 4 * kSecondNs).scale, 0.75);
  EXPECT_EQ(controller.decide(1e9, 6 * kSecondNs).scale, 1.0);
  EXPECT_EQ(controller.decide(1e9, 6 * kSecondNs).limited_by, StreamLimitedBy::kNothing);
}

TEST(StreamSettingsController, LearnsBitsPerPixelFromEncodedFrames) {
  StreamSettingsController controller(limits1080p());
  const StreamSettings first = controller.decide(100e6, 0);
  // The scene is twice as detailed as assumed: every frame is 2 bit/px at q90.
  for (int i = 0; i < 50; ++i) controller.observeFrame(first, static_cast<std::size_t>(2 * kFullFrameBits / 8));
  EXPECT_NEAR(controller.bitsPerPixelQ90(), 2.0, 1e-4);
  // Full scale at 15 Hz now needs 124 Mbit/s: 100 Mbit/s goes to scale 0.75.
  const StreamSettings learnt = controller.decide(100e6, 0);
  EXPECT_EQ(learnt.scale, 0.75);
  EXPECT_NEAR(learnt.fps, 100e6 / (2 * kFullFrameBits * 0.5625), 1e-3);
  // A frame at another scale and quality teaches the same quantity.
  StreamSettingsController other(limits1080p());
  StreamSettings small;
  small.scale = 0.5;
  small.quality = 50;
  for (int i = 0; i < 50; ++i)
    other.observeFrame(small, static_cast<std::size_t>(0.5 * kFullFrameBits * 0.25 * 0.373 / 8));
  EXPECT_NEAR(other.bitsPerPixelQ90(), 0.5, 1e-3);
}

TEST(StreamSettingsController, ExtremeTargetsAndSizes) {
  StreamSettingsController controller(limits1080p());
  for (const double nothing : {0.0, -5.0, std::numeric_limits<double>::quiet_NaN()}) {
    const StreamSettings s = controller.decide(nothing, 0);
    EXPECT_EQ(s.fps, 5) << nothing;
    EXPECT_EQ(s.scale, 0.35);
    EXPECT_EQ(s.quality, 50);
    EXPECT_TRUE(std::isfinite(s.predicted_bits_per_s));
  }
  StreamSettingsController unlimited(limits1080p());
  const StreamSettings s = unlimited.decide(std::numeric_limits<double>::infinity(), 0);
  EXPECT_EQ(s.fps, 45);
  EXPECT_EQ(s.scale, 1.0);
  // An empty frame teaches nothing.
  unlimited.observeFrame(s, 0);
  EXPECT_EQ(unlimited.bitsPerPixelQ90(), 1.0);
  // 2×4K at the default limits: 45 Hz needs 800 Mbit/s, 50 Mbit/s is already below 15 Hz at full size.
  StreamSettingsController uhd;
  EXPECT_NEAR(uhd.decide(1e12, 0).predicted_bits_per_s, 45 * 1.07 * 2 * 3840 * 2160, 1);
  EXPECT_LT(uhd.decide(50e6, 0).scale, 1.0);
}

TEST(StreamSettingsController, TheQualityCurveFollowsTheMeasuredTable) {
  EXPECT_DOUBLE_EQ(jpegSizeRelativeToQ90(90), 1.0);
  EXPECT_DOUBLE_EQ(jpegSizeRelativeToQ90(50), 0.373);
  EXPECT_DOUBLE_EQ(jpegSizeRelativeToQ90(95), 1.70);
  EXPECT_DOUBLE_EQ(jpegSizeRelativeToQ90(55), (0.373 + 0.413) / 2);
  EXPECT_DOUBLE_EQ(jpegSizeRelativeToQ90(0), 0.0);
  EXPECT_DOUBLE_EQ(jpegSizeRelativeToQ90(-3), 0.0);
  EXPECT_DOUBLE_EQ(jpegSizeRelativeToQ90(250), 2.4);
  for (int q = 1; q <= 100; ++q) EXPECT_GT(jpegSizeRelativeToQ90(q), jpegSizeRelativeToQ90(q - 1)) << q;
}

TEST(StreamSettingsController, ASlowSourceIsNotScaledForFramesItNeverSends) {
  // 1080p stereo at 1 bit per pixel: 4.15 Mbit a frame. 50 Mbit/s carries 12 frames a second at
  // full scale, not the 15 Hz floor: a 45 Hz camera is scaled down, a 10 Hz one need not be.
  const double bits = 2.0 * 1920 * 1080;
  StreamSettingsController fast(limits1080p()), slow(limits1080p());
  slow.setSourceFps(10);
  const StreamSettings f = fast.decide(50e6, 0);
  const StreamSettings s = slow.decide(50e6, 0);
  EXPECT_LT(f.scale, 1.0);
  EXPECT_DOUBLE_EQ(s.scale, 1.0);
  EXPECT_DOUBLE_EQ(s.fps, 10.0);
  EXPECT_EQ(s.quality, 90);
  EXPECT_EQ(s.limited_by, StreamLimitedBy::kNothing);
  EXPECT_LE(s.fps * bits, 50e6);
  // 30 Mbit/s: 7.2 frames at full scale; a 10 Hz source gives up rate to 7.2 Hz, then scale at its floor.
  const StreamSettings t = slow.decide(30e6, 1);
  EXPECT_LT(t.scale, 1.0);
  EXPECT_LE(t.fps, 10.0);
  // Back to nominal on a nonsense rate.
  slow.setSourceFps(std::numeric_limits<double>::quiet_NaN());
  EXPECT_LT(slow.decide(50e6, 2).scale, 1.0);
}

TEST(StreamSettingsController, BadLimitsAreNamed) {
  StreamSettingsLimits l = limits1080p();
  EXPECT_TRUE(checkStreamSettingsLimits(l).empty());
  l.scales = {0.5, 0.25};
  EXPECT_NE(checkStreamSettingsLimits(l).find("first scale"), std::string::npos);
  l = limits1080p();
  l.scales = {1.0, 0.5, 0.75};
  EXPECT_NE(checkStreamSettingsLimits(l).find("descend"), std::string::npos);
  l = limits1080p();
  l.min_fps = 20;
  EXPECT_NE(checkStreamSettingsLimits(l).find("min fps"), std::string::npos);
  l = limits1080p();
  l.min_quality = 95;
  EXPECT_NE(checkStreamSettingsLimits(l).find("quality"), std::string::npos);
  l = limits1080p();
  l.pixels_per_frame = 0;
  EXPECT_NE(checkStreamSettingsLimits(l).find("pixels"), std::string::npos);
  EXPECT_STREQ(streamLimitedByName(StreamLimitedBy::kQuality), "quality");
}

}  // namespace
}  // namespace telesphere::robot::video
