// SPDX-License-Identifier: MIT
/// @brief A decoded image's YUV planes exactly as the JPEG decoder wrote them (Y full size, Cb
///        and Cr subsampled): what the decode pool hands to the renderer through a shared pointer,
///        so the planes are never copied between decode and upload (DESIGN.md §4).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "robot/link/chroma_subsampling.h"

namespace telesphere::xr {

/// Planes with rows tightly packed (stride = width). For kGray, u and v are empty.
struct YuvPlanes {
  int width = 0;
  int height = 0;
  int chroma_width = 0;
  int chroma_height = 0;
  /// As the JPEG was encoded; nothing: planes not from a JPEG (any chroma size, SourceImage::yuv).
  std::optional<link::ChromaSubsampling> subsampling = link::ChromaSubsampling::k420;
  std::vector<std::uint8_t> y, u, v;
};

}  // namespace telesphere::xr
