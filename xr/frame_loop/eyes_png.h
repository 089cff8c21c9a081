// SPDX-License-Identifier: MIT
/// @brief Both eyes side by side (left | right) as one PNG: what the offscreen and desktop modes
///        leave behind as the operator's last view.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "shaders/offscreen_target.h"
#include "shaders/png_io.h"

namespace telesphere::xr::frame_loop {

/// Writes left | right (equal sizes, RGBA8) to `path`; false with the reason.
inline bool writeEyesPng(const std::string& path, const gl::OffscreenTarget& left, const gl::OffscreenTarget& right,
                         std::string* error) {
  const auto l = left.readRgba8(), r = right.readRgba8();
  const std::size_t w = std::size_t(left.width()), h = std::size_t(left.height());
  std::vector<std::uint8_t> both(2 * w * h * 4);
  for (std::size_t y = 0; y < h; ++y) {
    std::copy_n(l.begin() + std::ptrdiff_t(y * w * 4), w * 4, both.begin() + std::ptrdiff_t(y * 2 * w * 4));
    std::copy_n(r.begin() + std::ptrdiff_t(y * w * 4), w * 4, both.begin() + std::ptrdiff_t((y * 2 * w + w) * 4));
  }
  return gl::writePng(path, 2 * left.width(), left.height(), 4, both.data(), error);
}

/// "eyes_NNNNN.png" (NNNNN = frames) when every > 0 and frames is a multiple of it; empty when
/// no PNG is due.
inline std::string everyNthEyesPngName(std::uint64_t frames, int every) {
  if (every <= 0 || frames % static_cast<std::uint64_t>(every) != 0) return {};
  char name[64];
  std::snprintf(name, sizeof(name), "eyes_%05llu.png", static_cast<unsigned long long>(frames));
  return name;
}

/// `dir`/eyes_NNNNN.png when everyNthEyesPngName names one; true when nothing was due.
inline bool writeEveryNthEyesPng(const std::string& dir, std::uint64_t frames, int every,
                                 const gl::OffscreenTarget& left, const gl::OffscreenTarget& right,
                                 std::string* error) {
  const std::string name = everyNthEyesPngName(frames, every);
  if (name.empty() || dir.empty()) return true;
  return writeEyesPng(dir + "/" + name, left, right, error);
}

}  // namespace telesphere::xr::frame_loop
