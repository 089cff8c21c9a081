// SPDX-License-Identifier: MIT
/// @brief The codec topic's Bayer → JPEG figures (#34): what a camera's raw mosaic costs a core on
///        its way to a JPEG, through YUV 4:2:0 planes (cameras::DebayerToYuv420, then
///        JpegEncoder::encodeYuv420) and through today's RGB image, against the floor: TurboJPEG
///        encoding the same planes at the same quality. The mosaic comes from a raw file
///        (--bayer FILE.raw --size WxH --pattern RGGB|BGGR|GRBG|GBRG, 8-bit or 16-bit words with
///        --bits significant) or is sampled from the topic's RGB image with --pattern's layout. A
///        wide sensor's narrowing to 8 bits at capture (cameras::narrowSamplesTo8Bits) is a row of
///        its own: on the file's words, else on the sampled mosaic scaled to 12 bits.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "app/bench/bench_topic.h"

namespace telesphere::bench {

/// What the codec topic's options say about the mosaic.
struct BayerInputOptions {
  std::string raw_path;          ///< --bayer: 8-bit samples, or 16-bit little-endian words; rows unpadded
  int bits = 16;                 ///< --bits: significant bits of a 16-bit file's samples (9–16)
  std::string size;              ///< --size WxH of the raw file
  std::string pattern = "RGGB";  ///< --pattern: the colours of the top-left 2×2 cell
};
BayerInputOptions& bayerInputOptions();

/// Prints the table to ctx.out and returns the figures (bayer_to_jpeg_ms, floor_ms, ratio, …).
/// `rgb` (width × height × 3) is mosaicked when no raw file is given. Throws std::runtime_error
/// with the reason on bad options or an unreadable file.
nlohmann::json bayerToJpegFigures(const BenchContext& ctx, const std::uint8_t* rgb, int width, int height,
                                  const std::string& source);

}  // namespace telesphere::bench
