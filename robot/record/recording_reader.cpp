// SPDX-License-Identifier: MIT
/// @brief RecordingReader (see recording_reader.h).
#include "robot/record/recording_reader.h"

#include <limits>
#include <optional>


namespace telesphere::record {
namespace {

std::optional<RecordedTopic> topicNamed(const std::string& name) {
  for (const RecordedTopicInfo& info : recordedTopics())
    if (name == info.name) return info.topic;
  return std::nullopt;
}

}  // namespace

std::unique_ptr<RecordingReader> RecordingReader::open(const std::string& path, std::string* error) {
  auto reader = McapReader::open(path, error);
  if (!reader) return nullptr;
  std::unique_ptr<RecordingReader> session(new RecordingReader(std::move(reader)));
  if (!session->reader_->summary(&session->summary_, error)) {
    *error = path + ": " + *error;
    return nullptr;
  }
  bool frames = false;
  for (const auto& [id, c] : session->summary_.channels) frames = frames || c.topic == "/stereo/frame";
  if (!frames) {
    *error = path + ": not a telesphere session recording (no /stereo/frame channel)";
    return nullptr;
  }
  // The clock offset (written before the first message): the summary's times onto the steady
  // clock, as every time this class hands on.
  std::int64_t offset_ns = 0;
  McapReader::Extras extras;
  extras.on_metadata = [&](const McapMetadata& m) {
    if (const auto it = m.metadata.find(kSteadyToUtcKey); m.name == kRecordingMetadataName && it != m.metadata.end()) {
      try {
        offset_ns = std::stoll(it->second);
      } catch (...) {
      }
    }
    return true;
  };
  std::string ignored;
  session->reader_->forEachRecord([](const McapMessageView&) { return false; }, extras, &ignored);
  session->summary_.start_ns = static_cast<std::uint64_t>(static_cast<std::int64_t>(session->summary_.start_ns) - offset_ns);
  session->summary_.end_ns = static_cast<std::uint64_t>(static_cast<std::int64_t>(session->summary_.end_ns) - offset_ns);
  return session;
}

std::optional<RecordedCalibration> RecordingReader::firstCalibration() const {
  std::optional<RecordedCalibration> first;
  RecordedSessionVisitor visitor;
  visitor.calibration = [&](const RecordedCalibration& c) {
    first = c;
    return false;
  };
  visitor.before = [](std::int64_t) { return false; };  // a message came first: none at the start
  std::string ignored;
  forEach(visitor, &ignored);
  return first;
}

bool RecordingReader::forEach(const RecordedSessionVisitor& visitor, std::string* error) const {
  std::optional<std::int64_t> first_ns;
  bool bad_time = false;
  // The frame being joined: its StereoFrame, then its two images (same sequence).
  std::optional<RecordedFrame> joining;
  const auto skip = [this] {
    ++skipped_;
    return true;  // go on with the next message
  };
  // Log times on UTC come back onto the steady clock through the offset the metadata names.
  std::int64_t utc_offset_ns = 0;
  McapReader::Extras extras;
  extras.on_metadata = [&](const McapMetadata& m) {
    if (m.name != kRecordingMetadataName) return true;
    if (const auto it = m.metadata.find(kSteadyToUtcKey); it != m.metadata.end()) {
      try {
        utc_offset_ns = std::stoll(it->second);
      } catch (...) {
        ++skipped_;
      }
    }
    return true;
  };
  extras.on_attachment = [&](const McapAttachmentView& a) {
    const auto generation = calibrationGenerationOf(a.name);
    if (!generation || !visitor.calibration) return true;
    RecordedCalibration c;
    c.generation = *generation;
    c.log_time_ns = static_cast<std::int64_t>(a.log_time_ns) - utc_offset_ns;
    c.yaml.assign(reinterpret_cast<const char*>(a.data), a.size);
    return visitor.calibration(c);
  };
  const bool read = reader_->forEachRecord(
      [&](const McapMessageView& m) {
        const auto t = static_cast<std::int64_t>(m.log_time_ns) - utc_offset_ns;
        if (!first_ns) first_ns = t;
        // In double (times from a file): a message over a day after the first ends the walk.
        if ((double(t) - double(*first_ns)) > 86400e9) {
          *error = "a message logged more than a day after the first (" + m.channel->topic + ")";
          bad_time = true;
          return false;
        }
        if (visitor.before && !visitor.before(t)) return false;
        const auto topic = topicNamed(m.channel->topic);
        if (!topic || m.size > std::size_t(std::numeric_limits<int>::max())) return skip();  // protobuf's limit
        const int size = static_cast<int>(m.size);
        if (*topic == RecordedTopic::kStereoFrame) {
          if (joining) ++skipped_;  // the previous one never got both images
          joining.emplace();
          joining->log_time_ns = t;
          if (!joining->frame.ParseFromArray(m.data, size)) {
            joining.reset();
            return skip();
          }
          return true;
        }
        if (*topic == RecordedTopic::kLeftImage || *topic == RecordedTopic::kRightImage) {
          if (!joining || joining->frame.sequence() % (std::uint64_t(1) << 32) != m.sequence) return skip();
          const auto jpeg = compressedImageData(m.data, m.size);  // in place: the JPEG is copied once
          if (!jpeg) return skip();
          auto& side = *topic == RecordedTopic::kLeftImage ? joining->left : joining->right;
          side = std::make_shared<const std::vector<std::uint8_t>>(jpeg->begin(), jpeg->end());
          if (!joining->left || !joining->right) return true;
          RecordedFrame frame = std::move(*joining);
          joining.reset();
          ++frames_;
          return !visitor.frame || visitor.frame(std::move(frame));
        }
        return !visitor.message || visitor.message(*topic, m);
      },
      extras, error);
  return read && !bad_time;
}

}  // namespace telesphere::record
