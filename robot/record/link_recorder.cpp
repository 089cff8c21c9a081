// SPDX-License-Identifier: MIT
/// @brief LinkRecorder (see link_recorder.h).
#include "robot/record/link_recorder.h"

#include <unistd.h>

#include <chrono>
#include <ctime>

#include "robot/link/link_endpoints.h"

namespace telesphere::record {

std::size_t LinkRecorder::Item::bytes() const {
  std::size_t n = body.size() + (jpeg[0] ? jpeg[0]->size() : 0) + (jpeg[1] ? jpeg[1]->size() : 0) + sizeof(Item);
  for (const std::string& t : transforms) n += t.size();
  return n;
}

namespace {

std::string isoUtc(std::int64_t utc_ns) {
  const std::time_t seconds = static_cast<std::time_t>(utc_ns / 1'000'000'000);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char text[40];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace

std::shared_ptr<LinkRecorder> LinkRecorder::start(const std::string& path, const LinkRecorderOptions& options,
                                                        std::string* error) {
  auto writer = McapWriter::create(path, options.mcap, error);
  if (!writer) return nullptr;
  std::shared_ptr<LinkRecorder> r(new LinkRecorder(path, std::move(writer), options.max_queue_bytes));
  // The robot's steady clock onto UTC, once: every log time moves by the same offset, so a reader
  // gets the steady times back exactly (the metadata says the offset).
  const std::int64_t steady_now = link::linkNowNs();
  const std::int64_t utc_now =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  r->steady_to_utc_ns_ = utc_now - steady_now;
  std::map<std::string, std::string> metadata = options.metadata;
  metadata[kSteadyToUtcKey] = std::to_string(r->steady_to_utc_ns_);
  metadata["recording_started_utc"] = isoUtc(utc_now);
  metadata["software"] = std::string("telesphere ") + TELESPHERE_VERSION;
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) == 0) metadata.emplace("host", host);
  // One schema per message type (the two image channels share theirs).
  std::map<const google::protobuf::Descriptor*, std::uint16_t> schemas;
  for (const RecordedTopicInfo& t : recordedTopics()) {
    auto& schema = schemas[t.type];
    if (schema == 0) schema = r->writer_->addSchema(t.type->full_name(), "protobuf", fileDescriptorSetOf(t.type));
    r->channel_[static_cast<int>(t.topic)] = r->writer_->addChannel(t.name, schema, "protobuf");
  }
  r->writer_->writeMetadata(kRecordingMetadataName, metadata);
  if (!r->writer_->error().empty()) {
    *error = path + ": " + r->writer_->error();
    return nullptr;
  }
  r->thread_ = std::thread([raw = r.get()] { raw->run(); });
  return r;
}

LinkRecorder::LinkRecorder(std::string path, std::unique_ptr<McapWriter> writer, std::size_t max_queue_bytes)
    : path_(std::move(path)), writer_(std::move(writer)), max_queue_bytes_(max_queue_bytes) {}

LinkRecorder::~LinkRecorder() { stop(); }

void LinkRecorder::onLinkMessage(Direction direction, const link::proto::Envelope& envelope,
                                    const std::shared_ptr<const std::vector<std::uint8_t>>& left_jpeg,
                                    const std::shared_ptr<const std::vector<std::uint8_t>>& right_jpeg) {
  const auto topic = topicOf(envelope);
  if (!topic) return;
  Item item;
  item.topic = *topic;
  const std::int64_t now = link::linkNowNs();
  // Sent: our own stamp is the send time. Received: the arrival here, and the sender's stamp.
  // On UTC through the offset taken at the start.
  item.log_time_ns = static_cast<std::uint64_t>(
      (direction == Direction::kSent ? envelope.sender_clock_ns() : now) + steady_to_utc_ns_);
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
      // Where each camera was at its capture (when the frame's pose is known).
      for (const auto* image : {&f.left(), &f.right()})
        if (image->pose_source() != link::proto::POSE_SOURCE_UNKNOWN && image->has_t_robot_cam())
          item.transforms.push_back(frameTransform(image->capture_ns() + steady_to_utc_ns_, "robot",
                                                   image == &f.left() ? "cam_l" : "cam_r", image->t_robot_cam()));
      break;
    }
    case B::kRobotState: {
      const auto& state = envelope.robot_state();
      state.SerializeToString(&item.body);
      const std::int64_t t = state.t_ns() + steady_to_utc_ns_;
      if (state.has_t_robot_head()) item.transforms.push_back(frameTransform(t, "robot", "head", state.t_robot_head()));
      if (state.has_t_robot_flange())
        item.transforms.push_back(frameTransform(t, "robot", "flange", state.t_robot_flange()));
      break;
    }
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
      // A reply that names the calibration in use (apply, revert, get): attached if new.
      if (envelope.control_reply().has_calibration() && envelope.control_reply().calibration().generation() != 0)
        attachCalibration(envelope.control_reply().calibration(), envelope.sender_clock_ns());
      break;
    case B::kHeadTarget: envelope.head_target().SerializeToString(&item.body); break;
    case B::kXrStats: envelope.xr_stats().SerializeToString(&item.body); break;
    case B::kXrTelemetry: envelope.xr_telemetry().SerializeToString(&item.body); break;
    default: return;
  }
  const std::uint64_t messages = (item.topic == RecordedTopic::kStereoFrame ? 3 : 1) + item.transforms.size();
  enqueue(std::move(item), messages);
}

bool LinkRecorder::enqueue(Item&& item, std::uint64_t messages) {
  const std::size_t bytes = item.bytes();
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    if (!stats_.error.empty() || queue_bytes_ + bytes > max_queue_bytes_) {
      stats_.dropped += messages;
      return false;
    }
    queue_bytes_ += bytes;
    stats_.queue_bytes_max = std::max(stats_.queue_bytes_max, queue_bytes_);
    queue_.push_back(std::move(item));
  }
  wake_.notify_one();
  return true;
}

void LinkRecorder::attachCalibration(const link::proto::CalibrationInUse& calibration, std::int64_t t_ns) {
  {
    std::lock_guard lock(mutex_);
    if (!calibrations_attached_.insert(calibration.generation()).second) return;
  }
  Item item;
  item.attachment = true;
  item.topic = RecordedTopic::kControlReply;  // unused for an attachment
  item.name = calibrationAttachmentName(calibration.generation());
  item.log_time_ns = static_cast<std::uint64_t>(t_ns + steady_to_utc_ns_);
  item.publish_time_ns = item.log_time_ns;
  item.sequence = 0;
  item.body = "# telesphere calibration generation " + std::to_string(calibration.generation()) + ": " +
              calibration.source() + "\n" + calibration.yaml();
  enqueue(std::move(item), 0);
}

void LinkRecorder::writeItem(const Item& item) {
  if (item.attachment) {
    const bool attached = writer_->writeAttachment(item.log_time_ns, item.log_time_ns, item.name, "application/yaml",
                                                   item.body.data(), item.body.size());
    std::lock_guard lock(mutex_);
    stats_.attachments += attached ? 1 : 0;
    stats_.file_bytes = writer_->stats().bytes_written;
    if (!attached && stats_.error.empty()) stats_.error = writer_->error();
    return;
  }
  const auto ch = [&](RecordedTopic t) { return channel_[static_cast<int>(t)]; };
  const McapWriter::Part body{item.body.data(), item.body.size()};
  bool ok = writer_->writeParts(ch(item.topic), item.sequence, item.log_time_ns, item.publish_time_ns, &body, 1);
  std::uint64_t written = ok ? 1 : 0;
  if (ok && item.topic == RecordedTopic::kStereoFrame) {
    for (int side : {0, 1}) {
      const auto& jpeg = item.jpeg[side];
      const std::size_t n = jpeg ? jpeg->size() : 0;
      const std::string prefix =
          compressedImagePrefix(item.capture_ns[side] + steady_to_utc_ns_, side == 0 ? "cam_l" : "cam_r", n);
      const McapWriter::Part parts[2] = {{prefix.data(), prefix.size()}, {jpeg ? jpeg->data() : nullptr, n}};
      ok = ok && writer_->writeParts(ch(side == 0 ? RecordedTopic::kLeftImage : RecordedTopic::kRightImage),
                                     item.sequence, item.log_time_ns, item.publish_time_ns, parts, 2);
      written += ok ? 1 : 0;
    }
  }
  for (const std::string& transform : item.transforms) {
    ok = ok && writer_->write(ch(RecordedTopic::kTransforms), item.sequence, item.log_time_ns, item.publish_time_ns,
                              transform.data(), transform.size());
    written += ok ? 1 : 0;
  }
  std::lock_guard lock(mutex_);
  stats_.messages += written;
  if (item.topic == RecordedTopic::kStereoFrame && written >= 3) ++stats_.stereo_frames;
  stats_.payload_bytes = writer_->stats().message_bytes;
  stats_.file_bytes = writer_->stats().bytes_written;
  if (!ok) {
    stats_.dropped += (item.topic == RecordedTopic::kStereoFrame ? 3 : 1) + item.transforms.size() - written;
    if (stats_.error.empty()) stats_.error = writer_->error();
  }
}

void LinkRecorder::run() {
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
        if (!item.attachment) stats_.dropped += (item.topic == RecordedTopic::kStereoFrame ? 3 : 1) + item.transforms.size();
        continue;
      }
    }
    writeItem(item);
  }
}

bool LinkRecorder::stop() {
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

LinkRecorderStats LinkRecorder::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace telesphere::record
