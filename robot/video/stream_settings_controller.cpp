// SPDX-License-Identifier: MIT
#include "robot/video/stream_settings_controller.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace telesphere::robot::video {

std::string checkStreamSettingsLimits(const StreamSettingsLimits& l) {
  if (!(l.pixels_per_frame > 0)) return "pixels per frame must be > 0";
  if (!(l.min_fps > 0 && l.min_fps <= l.scale_floor_fps && l.scale_floor_fps <= l.nominal_fps))
    return "want 0 < min fps ≤ scale floor fps ≤ nominal fps";
  if (l.scales.empty() || l.scales.front() != 1.0) return "the first scale must be 1";
  for (std::size_t i = 1; i < l.scales.size(); ++i)
    if (!(l.scales[i] > 0 && l.scales[i] < l.scales[i - 1])) return "scales must descend and stay > 0";
  if (!(l.min_quality >= 1 && l.min_quality <= l.nominal_quality && l.nominal_quality <= 100))
    return "want 1 ≤ min quality ≤ nominal quality ≤ 100";
  if (!(l.scale_up_margin >= 1)) return "the scale-up margin must be ≥ 1";
  if (l.scale_hold_ns < 0) return "the scale hold must be ≥ 0";
  if (!(l.initial_bits_per_pixel_q90 > 0)) return "the initial bits per pixel must be > 0";
  if (!(l.feedback_weight > 0 && l.feedback_weight <= 1)) return "the feedback weight must be in (0, 1]";
  return {};
}

const char* streamLimitedByName(StreamLimitedBy reason) {
  switch (reason) {
    case StreamLimitedBy::kNothing: return "nominal";
    case StreamLimitedBy::kFrameRate: return "frame rate";
    case StreamLimitedBy::kScale: return "scale";
    case StreamLimitedBy::kQuality: return "quality";
    case StreamLimitedBy::kFrameRateBelowFloor: return "frame rate below floor";
    case StreamLimitedBy::kBitRate: return "bit rate";
    case StreamLimitedBy::kCount: break;
  }
  return "?";
}

double jpegSizeRelativeToQ90(int quality) {
  // (quality, size relative to q90): the 4:2:0 rows of xr/README.md's quality table, and the ends.
  static constexpr std::array<std::pair<int, double>, 9> kTable = {{
      {0, 0.0}, {10, 0.2}, {50, 0.373}, {60, 0.413}, {70, 0.477}, {80, 0.609}, {90, 1.0}, {95, 1.70}, {100, 2.4}}};
  const int q = std::clamp(quality, 0, 100);
  for (std::size_t i = 1; i < kTable.size(); ++i) {
    if (q <= kTable[i].first) {
      const auto [q0, r0] = kTable[i - 1];
      const auto [q1, r1] = kTable[i];
      return r0 + (r1 - r0) * (q - q0) / static_cast<double>(q1 - q0);
    }
  }
  return kTable.back().second;
}

StreamSettingsController::StreamSettingsController(StreamSettingsLimits limits)
    : limits_(std::move(limits)), bits_per_pixel_q90_(limits_.initial_bits_per_pixel_q90) {
  assert(checkStreamSettingsLimits(limits_).empty());
}

double StreamSettingsController::bitsPerFrame(double scale, int quality) const {
  return bits_per_pixel_q90_ * jpegSizeRelativeToQ90(quality) * limits_.pixels_per_frame * scale * scale;
}

void StreamSettingsController::setSourceFps(double fps) {
  source_fps_ = std::isfinite(fps) && fps > 0 ? fps : limits_.nominal_fps;
}

StreamSettings StreamSettingsController::decide(double target_bits_per_s, std::int64_t now_ns) {
  const double rate = std::isnan(target_bits_per_s) ? 0.0 : std::max(0.0, target_bits_per_s);
  const int qn = limits_.nominal_quality;
  // A source slower than nominal (a camera, or a robot PC, that cannot keep up) lowers both.
  const double nominal_fps = std::min(limits_.nominal_fps, source_fps_);
  const double floor_fps = std::min(limits_.scale_floor_fps, source_fps_);
  const auto fitsAtFloor = [&](std::size_t i, double margin) {
    return rate >= margin * bitsPerFrame(limits_.scales[i], qn) * floor_fps;
  };
  // Down at once while even the floor frame rate at nominal quality does not fit.
  while (scale_index_ + 1 < limits_.scales.size() && !fitsAtFloor(scale_index_, 1.0)) {
    ++scale_index_;
    ++stats_.scale_downs;
    last_scale_change_ns_ = now_ns;
    scale_changed_ever_ = true;
  }
  // Up one step when the next scale fits with margin and the last change is old enough.
  if (scale_index_ > 0 && fitsAtFloor(scale_index_ - 1, limits_.scale_up_margin) &&
      (!scale_changed_ever_ || now_ns - last_scale_change_ns_ >= limits_.scale_hold_ns)) {
    --scale_index_;
    ++stats_.scale_ups;
    last_scale_change_ns_ = now_ns;
    scale_changed_ever_ = true;
  }

  StreamSettings out;
  out.scale = limits_.scales[scale_index_];
  out.quality = qn;
  if (fitsAtFloor(scale_index_, 1.0)) {
    out.fps = std::min(nominal_fps, rate / bitsPerFrame(out.scale, qn));
    out.limited_by = scale_index_ > 0                ? StreamLimitedBy::kScale
                     : out.fps < nominal_fps ? StreamLimitedBy::kFrameRate
                                                     : StreamLimitedBy::kNothing;
  } else {
    // The smallest scale at the floor frame rate: the best quality that fits, else the lowest
    // quality at a lower frame rate.
    out.limited_by = StreamLimitedBy::kFrameRateBelowFloor;
    out.quality = limits_.min_quality;
    for (int q = qn - 1; q >= limits_.min_quality; --q) {
      if (bitsPerFrame(out.scale, q) * floor_fps <= rate) {
        out.quality = q;
        out.limited_by = StreamLimitedBy::kQuality;
        break;
      }
    }
    if (out.limited_by == StreamLimitedBy::kQuality) {
      out.fps = floor_fps;
    } else {
      const double fps = rate / bitsPerFrame(out.scale, out.quality);
      if (fps < limits_.min_fps) ++stats_.over_budget;
      out.fps = std::clamp(fps, std::min(limits_.min_fps, floor_fps), floor_fps);
    }
  }
  out.predicted_bits_per_s = bitsPerFrame(out.scale, out.quality) * out.fps;
  ++stats_.decisions_by_reason[static_cast<std::size_t>(out.limited_by)];
  return out;
}

void StreamSettingsController::observeFrame(const StreamSettings& used, std::size_t bytes) {
  const double pixels = limits_.pixels_per_frame * used.scale * used.scale;
  const double relative = jpegSizeRelativeToQ90(used.quality);
  if (!(pixels > 0 && relative > 0) || bytes == 0) return;
  const double bpp_q90 = 8.0 * static_cast<double>(bytes) / (pixels * relative);
  bits_per_pixel_q90_ += limits_.feedback_weight * (bpp_q90 - bits_per_pixel_q90_);
}

}  // namespace telesphere::robot::video
