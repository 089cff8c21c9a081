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
/// | /tf | foxglove.FrameTransform | robot → cam_l, cam_r (each frame, at its capture), head, flange (each state) |
///
/// Message log_time: UTC (ns since 1970) when it was sent or received: the robot's steady clock
/// plus the offset the "telesphere" metadata record names (steady_to_utc_offset_ns, taken once at
/// the start), so tools show the session's date and a reader gets the steady time back exactly;
/// publish_time: the sender's clock (the envelope's sender_clock_ns). A stereo frame's three
/// messages share the frame's sequence (MCAP sequence field) and log time.
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
  kTransforms,  ///< derived from frames and states as they are recorded, never sent on the link
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

/// A serialized foxglove.FrameTransform: the child frame's pose in the parent frame at t_ns.
std::string frameTransform(std::int64_t t_ns, const std::string& parent, const std::string& child,
                           const link::proto::Pose& T_parent_child);

/// The metadata record a recording opens with, and its keys.
inline constexpr const char* kRecordingMetadataName = "telesphere";
inline constexpr const char* kSteadyToUtcKey = "steady_to_utc_offset_ns";  ///< t_utc = t_steady + offset
/// Attachments of the calibration in use: "calibration-generation-<N>.yaml" (our YAML format).
std::string calibrationAttachmentName(std::uint64_t generation);
/// The generation an attachment's name says, or nothing (not a calibration attachment).
std::optional<std::uint64_t> calibrationGenerationOf(const std::string& attachment_name);

/// The `data` bytes of a serialized foxglove.CompressedImage where they lie in `message` (no copy:
/// a reader copies a JPEG once, not into a parsed message first); nothing when the bytes are not
/// such a message (fields in any order; the last `data` wins, an absent one is empty, as protobuf has it).
std::optional<std::span<const std::uint8_t>> compressedImageData(const std::uint8_t* message, std::size_t size);

}  // namespace telesphere::record
