// SPDX-License-Identifier: MIT
/// @brief libFuzzer target: arbitrary bytes as a received JPEG. Header parsing, the size limits
///        and decoding to YUV planes must never crash, read out of bounds or allocate beyond the
///        limit (libFuzzer's -rss_limit_mb catches the latter).
#include <cstddef>
#include <cstdint>
#include <string>

#include "xr/video/jpeg_decoder.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static telesphere::xr::video::JpegDecoder decoder;
  telesphere::xr::render::YuvPlanes planes;
  std::string error;
  // 2048 px per side keeps each run fast; the limit logic is the same as for 8192.
  decoder.decode({data, size}, 0, 0, 2048, planes, &error);
  return 0;
}
