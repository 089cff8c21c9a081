// SPDX-License-Identifier: MIT
/// @brief RecordedSession (see recorded_session.h).
#include "robot/record/recorded_session.h"

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

std::unique_ptr<RecordedSession> RecordedSession::open(const std::string& path, std::string* error) {
  auto reader = McapReader::open(path, error);
  if (!reader) return nullptr;
  std::unique_ptr<RecordedSession> session(new RecordedSession(std::move(reader)));
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
  return session;
}

bool RecordedSession::forEach(const RecordedSessionVisitor& visitor, std::string* error) const {
  std::optional<std::int64_t> first_ns;
  bool bad_time = false;
  // The frame being joined: its StereoFrame, then its two images (same sequence).
  std::optional<RecordedFrame> joining;
  const auto skip = [this] {
    ++skipped_;
    return true;  // go on with the next message
  };
  const bool read = reader_->forEachMessage(
      [&](const McapMessageView& m) {
        const auto t = static_cast<std::int64_t>(m.log_time_ns);
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
      error);
  return read && !bad_time;
}

}  // namespace telesphere::record
