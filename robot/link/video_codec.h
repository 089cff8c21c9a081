// SPDX-License-Identifier: MIT
/// @brief The video codecs the link can carry (#34): MJPEG (each image on its own, what the link
///        sends today), H.264 and HEVC (each image predicted from the last: a fraction of the
///        bytes for the same picture, at the price of key frames and a decoder that must see every
///        frame). One enum for robot and operator; names as the console and the command line
///        write them.
#pragma once

#include <optional>
#include <string_view>

namespace telesphere::link {

enum class VideoCodec { kMjpeg, kH264, kHevc };

constexpr const char* videoCodecName(VideoCodec codec) {
  switch (codec) {
    case VideoCodec::kMjpeg: return "mjpeg";
    case VideoCodec::kH264: return "h264";
    case VideoCodec::kHevc: return "hevc";
  }
  return "?";
}

/// "mjpeg", "h264" or "hevc" (also "h265"); nothing for any other name.
constexpr std::optional<VideoCodec> parseVideoCodec(std::string_view name) {
  if (name == "mjpeg") return VideoCodec::kMjpeg;
  if (name == "h264") return VideoCodec::kH264;
  if (name == "hevc" || name == "h265") return VideoCodec::kHevc;
  return std::nullopt;
}

}  // namespace telesphere::link
