// SPDX-License-Identifier: MIT
/// @brief 8-bit RGB/RGBA PNG files (libpng): offscreen frames for tests, docs and the still
///        command, and reading them back.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::gl {

/// Writes `pixels` (width·height·channels bytes, rows top first, channels 3 = RGB or 4 = RGBA)
/// to `path`. False, with the reason naming the file in out_error, when it cannot.
bool writePng(const std::string& path, int width, int height, int channels,
              const std::uint8_t* pixels, std::string* out_error = nullptr);

struct PngImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  ///< width·height·4, rows top first
};

/// Reads any PNG as 8-bit RGBA; nothing, with the reason naming the file in out_error, when it
/// cannot.
std::optional<PngImage> readPng(const std::string& path, std::string* out_error = nullptr);

}  // namespace telesphere::gl
