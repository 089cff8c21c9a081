// SPDX-License-Identifier: MIT
/// @brief What the video stream gives up when the link's rate falls (DESIGN.md §9): a target rate
///        (the bandwidth estimate, capped by the supervisor) becomes the frame rate, scale and JPEG
///        quality of the next frame, sacrificed in this order: frame rate down to 15 Hz first
///        (spherical re-rendering hides head motion at any frame rate; only scene motion suffers),
///        then scale, then quality, then frame rate below 15 Hz; restored in the reverse order.
///
///        Bits per frame are predicted as b(s, q) = bpp₉₀ · rel(q) · pixels · s², with pixels the
///        full-size pixels of one stereo frame (both cameras), s the scale (per axis), rel(q) JPEG
///        size relative to quality 90 (the 4:2:0 quality table of xr/README.md: q50 0.373, q60
///        0.413, q70 0.477, q80 0.609, q90 1, q95 1.70; linear between; extrapolated to 0.2 at q10,
///        0 at q0 and 2.4 at q100), and
///        bpp₉₀ learnt from the frames actually encoded (observeFrame, an exponential average).
///        Quality may change every frame (JPEG has no GOP); the scale steps down at once when even
///        15 Hz at nominal quality does not fit, and steps up only when the next scale fits with
///        `scale_up_margin` to spare and `scale_hold_ns` have passed since the last change.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace telesphere::robot::video {

struct StreamSettingsLimits {
  double pixels_per_frame = 2.0 * 3840 * 2160;  ///< full size, both cameras
  double nominal_fps = 45;
  double scale_floor_fps = 15;  ///< frame rate is given up down to here before the scale
  double min_fps = 5;
  std::vector<double> scales = {1.0, 0.75, 0.5, 0.35};  ///< per axis, descending, first 1
  int nominal_quality = 90;
  int min_quality = 50;
  double scale_up_margin = 1.25;      ///< the next scale up must fit this many times over
  std::int64_t scale_hold_ns = 2'000'000'000;
  double initial_bits_per_pixel_q90 = 1.07;  ///< the quality table's 4K frame at q90, 4:2:0
  double feedback_weight = 0.2;       ///< of a new frame's bits per pixel in the average
};

/// Nothing wrong: empty; else what is wrong.
std::string checkStreamSettingsLimits(const StreamSettingsLimits& limits);

/// Which sacrifice limited a decision (the link statistics count them).
/// kBitRate: H.264/HEVC (#34), whose encoder's rate follows the budget at the full frame rate and scale.
enum class StreamLimitedBy { kNothing, kFrameRate, kScale, kQuality, kFrameRateBelowFloor, kBitRate, kCount };
const char* streamLimitedByName(StreamLimitedBy reason);

struct StreamSettings {
  double fps = 0;
  double scale = 1;  ///< per axis
  int quality = 90;
  StreamLimitedBy limited_by = StreamLimitedBy::kNothing;
  double predicted_bits_per_s = 0;  ///< at these settings, with the current bpp₉₀
};

struct StreamSettingsStats {
  std::array<std::uint64_t, static_cast<std::size_t>(StreamLimitedBy::kCount)> decisions_by_reason{};
  std::uint64_t scale_downs = 0, scale_ups = 0;
  std::uint64_t over_budget = 0;  ///< decisions whose floor (min fps, min quality, smallest scale) still exceeds the target
};

/// JPEG size at quality q relative to quality 90 (see the brief), q in [1, 100].
double jpegSizeRelativeToQ90(int quality);

class StreamSettingsController {
 public:
  /// Limits must pass checkStreamSettingsLimits (asserted in debug builds).
  explicit StreamSettingsController(StreamSettingsLimits limits = {});

  /// The settings for the next frame at now_ns for a target rate (bit/s; NaN or < 0 count as 0).
  StreamSettings decide(double target_bits_per_s, std::int64_t now_ns);
  /// The rate frames actually arrive at (a camera or a robot PC slower than nominal_fps): the
  /// decisions then use min(nominal_fps, fps) and min(scale_floor_fps, fps), so a slow source
  /// is not scaled down for frames it never sends. NaN or ≤ 0: back to nominal_fps.
  void setSourceFps(double fps);
  /// A frame encoded at `used` came out `bytes` long: learn bits per pixel at q90 from it.
  void observeFrame(const StreamSettings& used, std::size_t bytes);

  /// Predicted bits of one stereo frame at scale s and quality q.
  double bitsPerFrame(double scale, int quality) const;
  double bitsPerPixelQ90() const { return bits_per_pixel_q90_; }
  const StreamSettingsStats& stats() const { return stats_; }

 private:
  StreamSettingsLimits limits_;
  double source_fps_ = 1e9;  ///< no limit until setSourceFps
  double bits_per_pixel_q90_;
  std::size_t scale_index_ = 0;
  std::int64_t last_scale_change_ns_ = 0;
  bool scale_changed_ever_ = false;
  StreamSettingsStats stats_;
};

}  // namespace telesphere::robot::video
