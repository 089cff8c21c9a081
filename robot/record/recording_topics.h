// SPDX-License-Identifier: MIT
/// @brief What a recording holds, topic by topic: each link message body on its own channel,
///        protobuf-encoded with its schema embedded (a FileDescriptorSet holding the message's
///        file and everything it imports), so that generic MCAP tools decode it without our code.
///
/// | topic | schema | what |
/// | --- | --- | --- |
/// | /stereo/frame | telesphere.link.proto.StereoFrame | poses, stamps, sizes of each sent pair |
/// | /stereo/left/compressed, /stereo/right/compressed | foxglove.CompressedImage | the JPEGs as sent |
/// | /robot/state, /robot/telemetry, /robot/health | RobotState, RobotTelemetry, RobotHealth | sent |
/// | /control/request, /control/reply | ControlRequest, ControlReply | received, sent |
/// | /xr/head_target, /xr/stats, /xr/telemetry | HeadTarget, XrStats, XrTelemetry | received |
///
/// Message log_time: the robot's steady clock when it was sent or received; publish_time: the
/// sender's clock (the envelope's sender_clock_ns). A stereo frame's three messages share the
/// frame's sequence (MCAP sequence field) and log time.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>

#include "robot/link/telesphere_link.pb.h"

namespace telesphere::record {

enum class RecordedTopic : std::uint8_t {
  kStereoFrame,
  kLeftImage,
  kRightImage,
  kRobotState,
  kRobotTelemetry,
  kRobotHealth,
  kControlRequest,
  kControlReply,
  kHeadTarget,
  kXrStats,
  kXrTelemetry,
  kCount
};

struct RecordedTopicInfo {
  RecordedTopic topic;
  const char* name;  ///< "/robot/state"
  const google::protobuf::Descriptor* type;
};

/// Every topic, in RecordedTopic order.
const std::vector<RecordedTopicInfo>& recordedTopics();

/// The topic an envelope's body is recorded on (none for pings, pongs, previews).
std::optional<RecordedTopic> topicOf(const link::proto::Envelope& envelope);

/// A serialized FileDescriptorSet of `type`'s file and its imports, dependencies first.
std::string fileDescriptorSetOf(const google::protobuf::Descriptor* type);

/// foxglove.CompressedImage in protobuf wire format, without its `data` bytes: the prefix to
/// which the caller appends exactly `jpeg_size` bytes of JPEG.
std::string compressedImagePrefix(std::int64_t capture_ns, const std::string& frame_id, std::size_t jpeg_size);

/// The `data` bytes of a serialized foxglove.CompressedImage where they lie in `message` (no copy:
/// a reader copies a JPEG once, not into a parsed message first); nothing when the bytes are not
/// such a message (fields in any order; the last `data` wins, an absent one is empty, as protobuf has it).
std::optional<std::span<const std::uint8_t>> compressedImageData(const std::uint8_t* message, std::size_t size);

}  // namespace telesphere::record
