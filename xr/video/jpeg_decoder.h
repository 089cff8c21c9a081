// SPDX-License-Identifier: MIT
/// @brief JPEG decoding on the operator side straight into the JPEG's native YUV planes (Y full
///        size, U and V subsampled), so the CPU never converts colour: the renderer does YUV→RGB
///        in the shader (DESIGN.md §4). The header is checked before anything is allocated.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "xr/render/yuv_planes.h"

namespace telesphere::xr::video {

enum class JpegDecodeError { kNone, kCorrupt, kTooLarge, kSizeMismatch, kUnsupported };

/// "none", "corrupt", "too_large", "size_mismatch", "unsupported".
const char* jpegDecodeErrorName(JpegDecodeError error);

/// What a JPEG header says, checked: the planes' sizes and the subsampling.
struct JpegHeader {
  render::PlaneLayout layout;
  link::ChromaSubsampling subsampling = link::ChromaSubsampling::k420;
};

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
                         int max_side, render::YuvPlanes& out, std::string* error);

  /// The two halves of decode(), for a caller that chooses the planes' memory by their size:
  /// readHeader checks as decode() does (nothing allocated); decodeInto writes the planes of
  /// that header to y, u, v (tightly packed; u, v null for greyscale).
  JpegDecodeError readHeader(std::span<const std::uint8_t> jpeg, int expected_width, int expected_height,
                             int max_side, JpegHeader* out, std::string* error);
  JpegDecodeError decodeInto(std::span<const std::uint8_t> jpeg, const JpegHeader& header, std::uint8_t* y,
                             std::uint8_t* u, std::uint8_t* v, std::string* error);

 private:
  void* handle_;
};

}  // namespace telesphere::xr::video
