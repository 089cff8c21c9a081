// SPDX-License-Identifier: MIT
/// @brief The codec topic's comparison of the link's codecs at Internet and LAN rates (#34):
///        MJPEG (its quality searched to fit the rate), H.264 and HEVC (libavcodec, latency
///        settings) on a moving sequence made from the topic's image (panning 4 px an image, fresh
///        sensor noise in each), at 2×1080p and 2×4K, 45 Hz, 10/20/50/100 Mbit/s for the pair:
///        bytes per stereo frame, SSIM and PSNR of the decoded image against its source, encode
///        and decode ms on one core, frames of latency the codec adds (keys under `codecs`).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "app/bench/bench_topic.h"

namespace telesphere::bench {

/// Prints the table to ctx.out and returns {"codecs": [...], "codec_goal": {...}}. `rgb` is the
/// topic's 4K image (width × height × 3); the 1080p runs use it halved.
nlohmann::json codecComparison(const BenchContext& ctx, const std::uint8_t* rgb, int width, int height);

}  // namespace telesphere::bench
