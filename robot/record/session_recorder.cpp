// SPDX-License-Identifier: MIT
/// @brief SessionRecorder (see session_recorder.h).
#include "robot/record/session_recorder.h"

#include "robot/link/link_endpoints.h"

namespace telesphere::record {

std::size_t SessionRecorder::Item::bytes() const {
  return body.size() + (jpeg[0] ? jpeg[0]->size() : 0) + (jpeg[1] ? jpeg[1]->size() : 0) + sizeof(Item);
}

std::shared_ptr<SessionRecorder> SessionRecorder::start(const std::string& path, const SessionRecorderOptions& options,
                                                        std::string* error) {
  auto writer = McapWriter::create(path, options.mcap, error);
  if (!writer) return nullptr;
  std::shared_ptr<SessionRecorder> r(new SessionRecorder(path, std::move(writer), options.max_queue_bytes));
  // One schema per message type (the two image channels share theirs).
  std::map<const google::protobuf::Descriptor*, std::uint16_t> schemas;
  for (const RecordedTopicInfo& t : recordedTopics()) {
    auto& schema = schemas[t.type];
    if (schema == 0) schema = r->writer_->addSchema(t.type->full_name(), "protobuf", fileDescriptorSetOf(t.type));
    r->channel_[static_cast<int>(t.topic)] = r->writer_->addChannel(t.name, schema, "protobuf");
  }
  if (!r->writer_->error().empty()) {
    *error = path + ": " + r->writer_->error();
    return nullptr;
  }
  r->thread_ = std::thread([raw = r.get()] { raw->run(); });
  return r;
}

SessionRecorder::SessionRecorder(std::string path, std::unique_ptr<McapWriter> writer, std::size_t max_queue_bytes)
    : path_(std::move(path)), writer_(std::move(writer)), max_queue_bytes_(max_queue_bytes) {}

SessionRecorder::~SessionRecorder() { stop(); }

void SessionRecorder::onLinkMessage(Direction direction, const link::proto::Envelope& envelope,
                                    const std::shared_ptr<const std::vector<std::uint8_t>>& left_jpeg,
                                    const std::shared_ptr<const std::vector<std::uint8_t>>& right_jpeg) {
  const auto topic = topicOf(envelope);
  if (!topic) return;
  Item item;
  item.topic = *topic;
  const auto now = static_cast<std::uint64_t>(link::linkNowNs());
  // Sent: our own stamp is the send time. Received: the arrival here, and the sender's stamp.
  item.log_time_ns = direction == Direction::kSent ? static_cast<std::uint64_t>(envelope.sender_clock_ns()) : now;
  item.publish_time_ns = static_cast<std::uint64_t>(envelope.sender_clock_ns());
  item.sequence = 0;
  using B = link::proto::Envelope::BodyCase;
  switch (envelope.body_case()) {
    case B::kStereoFrame: {
      const auto& f = envelope.stereo_frame();
      item.sequence = static_cast<std::uint32_t>(f.sequence());
      f.SerializeToString(&item.body);
      item.capture_ns[0] = f.left().capture_ns();
      item.capture_ns[1] = f.right().capture_ns();
      item.jpeg[0] = left_jpeg;
      item.jpeg[1] = right_jpeg;
      break;
    }
    case B::kRobotState: envelope.robot_state().SerializeToString(&item.body); break;
    case B::kRobotTelemetry:
      item.sequence = static_cast<std::uint32_t>(envelope.robot_telemetry().batch());
      envelope.robot_telemetry().SerializeToString(&item.body);
      break;
    case B::kRobotHealth: envelope.robot_health().SerializeToString(&item.body); break;
    case B::kControlRequest:
      item.sequence = static_cast<std::uint32_t>(envelope.control_request().id());
      envelope.control_request().SerializeToString(&item.body);
      break;
    case B::kControlReply:
      item.sequence = static_cast<std::uint32_t>(envelope.control_reply().id());
      envelope.control_reply().SerializeToString(&item.body);
      break;
    case B::kHeadTarget: envelope.head_target().SerializeToString(&item.body); break;
    case B::kXrStats: envelope.xr_stats().SerializeToString(&item.body); break;
    case B::kXrTelemetry: envelope.xr_telemetry().SerializeToString(&item.body); break;
    default: return;
  }
  const std::size_t bytes = item.bytes();
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    const std::uint64_t messages = item.topic == RecordedTopic::kStereoFrame ? 3 : 1;
    if (!stats_.error.empty() || queue_bytes_ + bytes > max_queue_bytes_) {
      stats_.dropped += messages;
      return;
    }
    queue_bytes_ += bytes;
    stats_.queue_bytes_max = std::max(stats_.queue_bytes_max, queue_bytes_);
    queue_.push_back(std::move(item));
  }
  wake_.notify_one();
}

void SessionRecorder::writeItem(const Item& item) {
  const auto ch = [&](RecordedTopic t) { return channel_[static_cast<int>(t)]; };
  const McapWriter::Part body{item.body.data(), item.body.size()};
  bool ok = writer_->writeParts(ch(item.topic), item.sequence, item.log_time_ns, item.publish_time_ns, &body, 1);
  std::uint64_t written = ok ? 1 : 0;
  if (ok && item.topic == RecordedTopic::kStereoFrame) {
    for (int side : {0, 1}) {
      const auto& jpeg = item.jpeg[side];
      const std::size_t n = jpeg ? jpeg->size() : 0;
      const std::string prefix = compressedImagePrefix(item.capture_ns[side], side == 0 ? "cam_l" : "cam_r", n);
      const McapWriter::Part parts[2] = {{prefix.data(), prefix.size()}, {jpeg ? jpeg->data() : nullptr, n}};
      ok = ok && writer_->writeParts(ch(side == 0 ? RecordedTopic::kLeftImage : RecordedTopic::kRightImage),
                                     item.sequence, item.log_time_ns, item.publish_time_ns, parts, 2);
      written += ok ? 1 : 0;
    }
  }
  std::lock_guard lock(mutex_);
  stats_.messages += written;
  if (item.topic == RecordedTopic::kStereoFrame && written == 3) ++stats_.stereo_frames;
  stats_.payload_bytes = writer_->stats().message_bytes;
  stats_.file_bytes = writer_->stats().bytes_written;
  if (!ok) {
    stats_.dropped += (item.topic == RecordedTopic::kStereoFrame ? 3 : 1) - written;
    if (stats_.error.empty()) stats_.error = writer_->error();
  }
}

void SessionRecorder::run() {
  for (;;) {
    Item item;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping and drained
      item = std::move(queue_.front());
      queue_.pop_front();
      queue_bytes_ -= item.bytes();
      if (!stats_.error.empty()) {
        stats_.dropped += item.topic == RecordedTopic::kStereoFrame ? 3 : 1;
        continue;
      }
    }
    writeItem(item);
  }
}

bool SessionRecorder::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopped_) return stats_.error.empty() && stats_.dropped == 0;
    stopping_ = true;
    stopped_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  const bool closed = writer_->close();
  std::lock_guard lock(mutex_);
  stats_.file_bytes = writer_->stats().bytes_written;
  if (!closed && stats_.error.empty()) stats_.error = writer_->error();
  return stats_.error.empty() && stats_.dropped == 0;
}

SessionRecorderStats SessionRecorder::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace telesphere::record
