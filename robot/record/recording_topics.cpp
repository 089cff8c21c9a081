// SPDX-License-Identifier: MIT
/// @brief The recording's topics and schemas (see recording_topics.h).
#include "robot/record/recording_topics.h"

#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>

#include <functional>
#include <limits>
#include <set>

#include "robot/record/foxglove_compressed_image.pb.h"
#include "robot/record/foxglove_frame_transform.pb.h"

namespace telesphere::record {

const std::vector<RecordedTopicInfo>& recordedTopics() {
  namespace p = link::proto;
  static const std::vector<RecordedTopicInfo> topics{
      {RecordedTopic::kStereoFrame, "/stereo/frame", p::StereoFrame::descriptor()},
      {RecordedTopic::kLeftImage, "/stereo/left/compressed", foxglove::CompressedImage::descriptor()},
      {RecordedTopic::kRightImage, "/stereo/right/compressed", foxglove::CompressedImage::descriptor()},
      {RecordedTopic::kRobotState, "/robot/state", p::RobotState::descriptor()},
      {RecordedTopic::kRobotTelemetry, "/robot/telemetry", p::RobotTelemetry::descriptor()},
      {RecordedTopic::kRobotHealth, "/robot/health", p::RobotHealth::descriptor()},
      {RecordedTopic::kControlRequest, "/control/request", p::ControlRequest::descriptor()},
      {RecordedTopic::kControlReply, "/control/reply", p::ControlReply::descriptor()},
      {RecordedTopic::kHeadTarget, "/xr/head_target", p::HeadTarget::descriptor()},
      {RecordedTopic::kXrStats, "/xr/stats", p::XrStats::descriptor()},
      {RecordedTopic::kXrTelemetry, "/xr/telemetry", p::XrTelemetry::descriptor()},
      {RecordedTopic::kTransforms, "/tf", foxglove::FrameTransform::descriptor()},
  };
  return topics;
}

std::optional<RecordedTopic> topicOf(const link::proto::Envelope& envelope) {
  using B = link::proto::Envelope::BodyCase;
  switch (envelope.body_case()) {
    case B::kStereoFrame: return RecordedTopic::kStereoFrame;
    case B::kRobotState: return RecordedTopic::kRobotState;
    case B::kRobotTelemetry: return RecordedTopic::kRobotTelemetry;
    case B::kRobotHealth: return RecordedTopic::kRobotHealth;
    case B::kControlRequest: return RecordedTopic::kControlRequest;
    case B::kControlReply: return RecordedTopic::kControlReply;
    case B::kHeadTarget: return RecordedTopic::kHeadTarget;
    case B::kXrStats: return RecordedTopic::kXrStats;
    case B::kXrTelemetry: return RecordedTopic::kXrTelemetry;
    default: return std::nullopt;
  }
}

std::string fileDescriptorSetOf(const google::protobuf::Descriptor* type) {
  google::protobuf::FileDescriptorSet set;
  std::set<std::string> added;
  const std::function<void(const google::protobuf::FileDescriptor*)> add = [&](const google::protobuf::FileDescriptor* f) {
    if (!added.insert(f->name()).second) return;
    for (int i = 0; i < f->dependency_count(); ++i) add(f->dependency(i));
    f->CopyTo(set.add_file());
  };
  add(type->file());
  return set.SerializeAsString();
}

namespace {
void varint(std::string& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>(v | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}
void lengthDelimited(std::string& out, int field, std::size_t size) {
  varint(out, (std::uint64_t(field) << 3) | 2);
  varint(out, size);
}
}  // namespace

std::string compressedImagePrefix(std::int64_t capture_ns, const std::string& frame_id, std::size_t jpeg_size) {
  std::string timestamp;  // google.protobuf.Timestamp {seconds = 1, nanos = 2}, floor division
  std::int64_t seconds = capture_ns / 1'000'000'000;
  std::int64_t nanos = capture_ns % 1'000'000'000;
  if (nanos < 0) {
    nanos += 1'000'000'000;
    --seconds;
  }
  if (seconds != 0) {
    varint(timestamp, (1u << 3) | 0);
    varint(timestamp, static_cast<std::uint64_t>(seconds));
  }
  if (nanos != 0) {
    varint(timestamp, (2u << 3) | 0);
    varint(timestamp, static_cast<std::uint64_t>(nanos));
  }
  std::string out;
  lengthDelimited(out, 1, timestamp.size());
  out += timestamp;
  lengthDelimited(out, 4, frame_id.size());
  out += frame_id;
  lengthDelimited(out, 3, 4);
  out += "jpeg";
  lengthDelimited(out, 2, jpeg_size);
  return out;
}

std::optional<std::span<const std::uint8_t>> compressedImageData(const std::uint8_t* message, std::size_t size) {
  using google::protobuf::internal::WireFormatLite;
  if (size > static_cast<std::size_t>(std::numeric_limits<int>::max())) return std::nullopt;
  google::protobuf::io::CodedInputStream in(message, static_cast<int>(size));
  std::optional<std::span<const std::uint8_t>> data;
  while (const std::uint32_t tag = in.ReadTag()) {
    if (WireFormatLite::GetTagFieldNumber(tag) == 2 &&
        WireFormatLite::GetTagWireType(tag) == WireFormatLite::WIRETYPE_LENGTH_DELIMITED) {
      std::uint32_t length = 0;
      if (!in.ReadVarint32(&length)) return std::nullopt;
      const auto at = static_cast<std::size_t>(in.CurrentPosition());
      if (length > size - at || !in.Skip(static_cast<int>(length))) return std::nullopt;
      data = std::span<const std::uint8_t>(message + at, length);
    } else if (!WireFormatLite::SkipField(&in, tag)) {
      return std::nullopt;
    }
  }
  if (!in.ConsumedEntireMessage()) return std::nullopt;
  return data.value_or(std::span<const std::uint8_t>());  // absent: empty, as protobuf has it
}

std::string frameTransform(std::int64_t t_ns, const std::string& parent, const std::string& child,
                           const link::proto::Pose& T_parent_child) {
  foxglove::FrameTransform t;
  t.mutable_timestamp()->set_seconds(t_ns / 1'000'000'000);
  t.mutable_timestamp()->set_nanos(static_cast<int>(t_ns % 1'000'000'000));
  t.set_parent_frame_id(parent);
  t.set_child_frame_id(child);
  t.mutable_translation()->set_x(T_parent_child.tx());
  t.mutable_translation()->set_y(T_parent_child.ty());
  t.mutable_translation()->set_z(T_parent_child.tz());
  t.mutable_rotation()->set_x(T_parent_child.qx());
  t.mutable_rotation()->set_y(T_parent_child.qy());
  t.mutable_rotation()->set_z(T_parent_child.qz());
  t.mutable_rotation()->set_w(T_parent_child.qw());
  return t.SerializeAsString();
}

std::string calibrationAttachmentName(std::uint64_t generation) {
  return "calibration-generation-" + std::to_string(generation) + ".yaml";
}

std::optional<std::uint64_t> calibrationGenerationOf(const std::string& name) {
  const std::string prefix = "calibration-generation-", suffix = ".yaml";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return std::nullopt;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 19)
    return std::nullopt;
  return std::stoull(digits);
}

}  // namespace telesphere::record
