// SPDX-License-Identifier: MIT
/// @brief The link's enums ↔ their protobuf values, in one place (the enums themselves,
///        robot/link/visual_mode.h, depth_proxy.h, chroma_subsampling.h and video_codec.h, need no protobuf).
#pragma once

#include <optional>

#include "robot/link/chroma_subsampling.h"
#include "robot/link/depth_proxy.h"
#include "robot/link/telesphere_link.pb.h"
#include "robot/link/video_codec.h"
#include "robot/link/visual_mode.h"

namespace telesphere::link {

inline proto::VisualMode toProto(VisualMode mode) {
  switch (mode) {
    case VisualMode::kFull6d: return proto::VISUAL_MODE_FULL6D;
    case VisualMode::kOrientation3d: return proto::VISUAL_MODE_ORIENTATION3D;
    case VisualMode::kFixed: return proto::VISUAL_MODE_FIXED;
  }
  return proto::VISUAL_MODE_UNSPECIFIED;
}

/// Nothing for VISUAL_MODE_UNSPECIFIED or a value this build does not know.
inline std::optional<VisualMode> fromProto(proto::VisualMode mode) {
  switch (mode) {
    case proto::VISUAL_MODE_FULL6D: return VisualMode::kFull6d;
    case proto::VISUAL_MODE_ORIENTATION3D: return VisualMode::kOrientation3d;
    case proto::VISUAL_MODE_FIXED: return VisualMode::kFixed;
    default: return std::nullopt;
  }
}

inline proto::DepthProxyProto toProto(DepthProxy proxy) {
  switch (proxy) {
    case DepthProxy::kFixed: return proto::DEPTH_PROXY_FIXED;
    case DepthProxy::kRadius: return proto::DEPTH_PROXY_RADIUS;
    case DepthProxy::kGrid: return proto::DEPTH_PROXY_GRID;
  }
  return proto::DEPTH_PROXY_UNSPECIFIED;
}

/// Nothing for DEPTH_PROXY_UNSPECIFIED (nobody chose) or a value this build does not know.
inline std::optional<DepthProxy> fromProto(proto::DepthProxyProto proxy) {
  switch (proxy) {
    case proto::DEPTH_PROXY_FIXED: return DepthProxy::kFixed;
    case proto::DEPTH_PROXY_RADIUS: return DepthProxy::kRadius;
    case proto::DEPTH_PROXY_GRID: return DepthProxy::kGrid;
    default: return std::nullopt;
  }
}

inline proto::ChromaSubsampling toProto(ChromaSubsampling s) {
  switch (s) {
    case ChromaSubsampling::k420: return proto::CHROMA_420;
    case ChromaSubsampling::k422: return proto::CHROMA_422;
    case ChromaSubsampling::k444: return proto::CHROMA_444;
    case ChromaSubsampling::kGray: return proto::CHROMA_GRAY;
  }
  return proto::CHROMA_420;
}

/// Nothing for a value this build does not know (a newer peer).
inline std::optional<ChromaSubsampling> fromProto(proto::ChromaSubsampling s) {
  switch (s) {
    case proto::CHROMA_420: return ChromaSubsampling::k420;
    case proto::CHROMA_422: return ChromaSubsampling::k422;
    case proto::CHROMA_444: return ChromaSubsampling::k444;
    case proto::CHROMA_GRAY: return ChromaSubsampling::kGray;
    default: return std::nullopt;
  }
}

inline proto::VideoCodecProto toProto(VideoCodec codec) {
  switch (codec) {
    case VideoCodec::kMjpeg: return proto::VIDEO_CODEC_MJPEG;
    case VideoCodec::kH264: return proto::VIDEO_CODEC_H264;
    case VideoCodec::kHevc: return proto::VIDEO_CODEC_HEVC;
  }
  return proto::VIDEO_CODEC_MJPEG;
}

/// Nothing for a value this build does not know (a newer peer).
inline std::optional<VideoCodec> fromProto(proto::VideoCodecProto codec) {
  switch (codec) {
    case proto::VIDEO_CODEC_MJPEG: return VideoCodec::kMjpeg;
    case proto::VIDEO_CODEC_H264: return VideoCodec::kH264;
    case proto::VIDEO_CODEC_HEVC: return VideoCodec::kHevc;
    default: return std::nullopt;
  }
}

}  // namespace telesphere::link
