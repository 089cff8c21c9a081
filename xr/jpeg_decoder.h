// SPDX-License-Identifier: MIT
/// @brief JPEG decoding on the operator side straight into the JPEG's native YUV planes (Y full
///        size, U and V subsampled), so the CPU never converts colour: the renderer does YUV→RGB
///        in the shader (DESIGN.md §4). The header is checked before anything is allocated.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace telesphere::xr {

enum class JpegSubsampling { k420, k422, k444, kGray, kOther };

/// A decoded image's planes, rows tightly packed. For kGray, u and v are empty.
struct YuvPlanes {
  int width = 0;
  int height = 0;
  int chroma_width = 0;
  int chroma_height = 0;
  JpegSubsampling subsampling = JpegSubsampling::k420;
  std::vector<std::uint8_t> y, u, v;
};

enum class JpegDecodeError { kNone, kCorrupt, kTooLarge, kSizeMismatch, kUnsupported };

class JpegDecoder {
 public:
  JpegDecoder();
  ~JpegDecoder();
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;

  /// Decodes `jpeg` into out (its buffers reused). The image must be expected_width ×
  /// expected_height (as the link message said; 0 accepts any size up to max_side) and no side
  /// larger than max_side. On failure out is left unspecified and *error says why.
  JpegDecodeError decode(std::span<const std::uint8_t> jpeg, int expected_width, int expected_height,
                         int max_side, YuvPlanes& out, std::string* error);

 private:
  void* handle_;
};

}  // namespace telesphere::xr
