// SPDX-License-Identifier: MIT
/// @brief The session recorder on a real LinkServer with a real LinkClient over loopback: stereo
///        frames, state, telemetry, health, a control request and its reply, head targets and XR
///        stats all land in the file on their topics; every message decodes through the schema
///        embedded in the file alone (a DescriptorPool built from its FileDescriptorSet, dynamic
///        messages: no generated code); the images are foxglove.CompressedImage holding the JPEG
///        bytes as sent; log times and image stamps on UTC through the offset the metadata names;
///        camera and head poses on /tf as foxglove.FrameTransform; the calibration in use attached
///        at the start and when a reply names a new one. A full queue drops and counts instead of
///        waiting; a bad path is refused.
#include <gtest/gtest.h>

#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>

#include <filesystem>
#include <thread>

#include "robot/link/link_client.h"
#include "robot/link/link_server.h"
#include "robot/record/foxglove_compressed_image.pb.h"
#include "robot/record/foxglove_frame_transform.pb.h"
#include "robot/record/mcap_reader.h"
#include "robot/record/link_recorder.h"

namespace telesphere::record {
namespace {

namespace proto = link::proto;
constexpr int kPort = 28140;

std::filesystem::path tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("telesphere-rec-" + std::to_string(getpid()) + "-" + name);
}

link::SharedBytes bytesOf(std::size_t n, std::uint8_t seed) {
  auto v = std::make_shared<std::vector<std::uint8_t>>(n);
  for (std::size_t i = 0; i < n; ++i) (*v)[i] = static_cast<std::uint8_t>(seed + i * 7);
  return v;
}

/// Decodes `data` as `schema` using only the schema's embedded FileDescriptorSet.
bool decodesWithEmbeddedSchema(const McapSchema& schema, const std::uint8_t* data, std::size_t size,
                               std::string* text) {
  google::protobuf::FileDescriptorSet set;
  if (schema.encoding != "protobuf" || !set.ParseFromString(schema.data)) return false;
  google::protobuf::DescriptorPool pool;
  for (const auto& file : set.file())
    if (pool.BuildFile(file) == nullptr) return false;
  const google::protobuf::Descriptor* type = pool.FindMessageTypeByName(schema.name);
  if (type == nullptr) return false;
  google::protobuf::DynamicMessageFactory factory(&pool);
  std::unique_ptr<google::protobuf::Message> message(factory.GetPrototype(type)->New());
  if (!message->ParseFromArray(data, static_cast<int>(size))) return false;
  *text = message->ShortDebugString();
  return true;
}

TEST(LinkRecorder, EverythingOnTheLinkLandsOnItsTopicAndDecodesFromTheFileAlone) {
  const std::string path = tempFile("session.mcap").string();
  link::LinkEndpoints endpoints;
  endpoints.base_port = kPort;
  link::LinkServer server(endpoints);
  server.setControlHandler([](const proto::ControlRequest&) {
    proto::ControlReply reply;
    reply.set_ok(true);
    reply.mutable_calibration()->set_generation(3);  // as after an apply_calibration
    reply.mutable_calibration()->set_yaml("cameras: []\n");
    reply.mutable_calibration()->set_source("a test apply");
    return reply;
  });
  std::string error;
  LinkRecorderOptions options;
  options.mcap.compression = McapCompression::kLz4;
  options.mcap.chunk_size = 64 * 1024;
  options.metadata = {{"arm", "test arm"}};
  auto recorder = LinkRecorder::start(path, options, &error);
  ASSERT_TRUE(recorder) << error;
  const std::int64_t utc = recorder->steadyToUtcOffsetNs();
  proto::CalibrationInUse startup;
  startup.set_generation(1);
  startup.set_yaml("cameras: []\n");
  startup.set_source("--calib test.yaml");
  recorder->attachCalibration(startup, link::linkNowNs());
  recorder->attachCalibration(startup, link::linkNowNs());  // once per generation
  server.setTap(recorder);
  link::LinkClient client(endpoints);

  std::vector<link::SharedBytes> lefts, rights;
  for (int i = 0; i < 20; ++i) {
    proto::StereoFrame frame;
    frame.set_sequence(100 + std::uint64_t(i));
    frame.mutable_left()->set_capture_ns(5'000'000'000LL + i * 22'222'222LL);
    frame.mutable_right()->set_capture_ns(5'000'000'000LL + i * 22'222'222LL + 17);
    frame.mutable_left()->set_width(64);
    if (i % 2 == 0) {  // every other frame with measured camera poses: two transforms each
      for (auto* image : {frame.mutable_left(), frame.mutable_right()}) {
        image->set_pose_source(proto::POSE_SOURCE_JOINT_BUFFER);
        image->mutable_t_robot_cam()->set_tx(image == frame.mutable_left() ? -0.03 : 0.03);
        image->mutable_t_robot_cam()->set_qw(1.0);
      }
    }
    lefts.push_back(bytesOf(30000 + std::size_t(i), std::uint8_t(i)));
    rights.push_back(bytesOf(31000 + std::size_t(i), std::uint8_t(i + 1)));
    server.publishStereoFrame(frame, lefts.back(), rights.back());
    proto::RobotState state;
    state.set_t_ns(i);
    state.mutable_t_robot_head()->set_tz(0.45);  // head and flange: two transforms per state
    state.mutable_t_robot_head()->set_qw(1.0);
    state.mutable_t_robot_flange()->set_qw(1.0);
    server.publishRobotState(state);
  }
  proto::RobotTelemetry telemetry;
  telemetry.set_batch(7);
  server.publishTelemetry(telemetry);
  server.publishHealth(proto::RobotHealth{});
  // Received: a control request (and the reply sent back), head targets, XR stats.
  proto::ControlRequest request;
  request.set_id(42);
  const auto reply = client.request(request, std::chrono::seconds(5));
  ASSERT_TRUE(reply && reply->ok());
  for (int i = 1; i <= 3; ++i) {
    proto::HeadTarget target;
    target.set_t_ns(i);
    client.sendHeadTarget(target);
  }
  client.sendXrStats(proto::XrStats{});
  // The uplink is asynchronous: wait (bounded) until the server has taken the last head target.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!(server.latestHeadTarget() && server.latestHeadTarget()->t_ns() == 3) &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_TRUE(server.latestHeadTarget());
  const auto xr_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!client.latestXrStats() && std::chrono::steady_clock::now() < xr_deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // republished once the server took it
  server.setTap(nullptr);
  EXPECT_TRUE(recorder->stop());
  const LinkRecorderStats stats = recorder->stats();
  EXPECT_EQ(stats.dropped, 0u);
  EXPECT_EQ(stats.stereo_frames, 20u);
  EXPECT_TRUE(stats.error.empty()) << stats.error;

  const auto reader = McapReader::open(path, &error);
  ASSERT_TRUE(reader) << error;
  std::map<std::string, int> counts;
  int decoded = 0, images = 0, transforms_with_cam = 0;
  std::vector<std::string> attachments;
  std::map<std::string, std::string> metadata;
  McapReader::Extras extras;
  extras.on_attachment = [&](const McapAttachmentView& a) {
    attachments.push_back(a.name);
    EXPECT_EQ(a.media_type, "application/yaml");
    EXPECT_NE(std::string(reinterpret_cast<const char*>(a.data), a.size).find("cameras: []"), std::string::npos);
    return true;
  };
  extras.on_metadata = [&](const McapMetadata& m) {
    EXPECT_EQ(m.name, "telesphere");
    metadata = m.metadata;
    return true;
  };
  bool ok = reader->forEachRecord(
      [&](const McapMessageView& m) {
        ++counts[m.channel->topic];
        std::string text;
        const McapSchema& schema = reader->schemasSeen().at(m.channel->schema_id);
        EXPECT_EQ(m.channel->message_encoding, "protobuf");
        if (decodesWithEmbeddedSchema(schema, m.data, m.size, &text)) ++decoded;
        else ADD_FAILURE() << m.channel->topic << " does not decode with its embedded schema " << schema.name;
        if (m.channel->topic == "/stereo/left/compressed" || m.channel->topic == "/stereo/right/compressed") {
          foxglove::CompressedImage image;
          EXPECT_TRUE(image.ParseFromArray(m.data, static_cast<int>(m.size)));
          const bool left = m.channel->topic == "/stereo/left/compressed";
          const int i = static_cast<int>(m.sequence) - 100;
          EXPECT_GE(i, 0);
          EXPECT_LT(i, 20);
          if (i < 0 || i >= 20) return true;
          const auto& jpeg = left ? *lefts[std::size_t(i)] : *rights[std::size_t(i)];
          EXPECT_EQ(image.data(), std::string(jpeg.begin(), jpeg.end()));
          EXPECT_EQ(image.format(), "jpeg");
          EXPECT_EQ(image.frame_id(), left ? "cam_l" : "cam_r");
          const std::int64_t capture = 5'000'000'000LL + i * 22'222'222LL + (left ? 0 : 17);
          EXPECT_EQ(image.timestamp().seconds() * 1'000'000'000LL + image.timestamp().nanos(), capture + utc);
          ++images;
        }
        if (m.channel->topic == "/stereo/frame") {
          proto::StereoFrame f;
          EXPECT_TRUE(f.ParseFromArray(m.data, static_cast<int>(m.size)));
          EXPECT_EQ(f.sequence(), m.sequence);
          EXPECT_EQ(f.stamps().sent_ns() + utc, static_cast<std::int64_t>(m.log_time_ns));  // log time = sent, on UTC
          EXPECT_EQ(f.left().jpeg_bytes(), lefts[f.sequence() - 100]->size());
        }
        if (m.channel->topic == "/tf") {
          foxglove::FrameTransform t;
          EXPECT_TRUE(t.ParseFromArray(m.data, static_cast<int>(m.size)));
          EXPECT_EQ(t.parent_frame_id(), "robot");
          if (t.child_frame_id() == "cam_l") {
            ++transforms_with_cam;
            EXPECT_DOUBLE_EQ(t.translation().x(), -0.03);
            const int i = static_cast<int>(m.sequence) - 100;
            EXPECT_EQ(t.timestamp().seconds() * 1'000'000'000LL + t.timestamp().nanos(),
                      5'000'000'000LL + i * 22'222'222LL + utc);  // at the capture, on UTC
          }
          if (t.child_frame_id() == "head") {
            EXPECT_DOUBLE_EQ(t.translation().z(), 0.45);
          }
        }
        return true;
      },
      extras, &error);
  EXPECT_TRUE(ok) << error;
  EXPECT_EQ(counts["/stereo/frame"], 20);
  EXPECT_EQ(counts["/stereo/left/compressed"], 20);
  EXPECT_EQ(counts["/stereo/right/compressed"], 20);
  EXPECT_EQ(counts["/robot/state"], 20);
  EXPECT_EQ(counts["/robot/telemetry"], 1);
  EXPECT_GE(counts["/robot/health"], 1);
  EXPECT_EQ(counts["/control/request"], 1);
  EXPECT_EQ(counts["/control/reply"], 1);
  EXPECT_EQ(counts["/xr/head_target"], 3);
  EXPECT_EQ(counts["/xr/stats"], 1);
  EXPECT_EQ(counts["/tf"], 10 * 2 + 20 * 2);
  EXPECT_EQ(transforms_with_cam, 10);
  EXPECT_EQ(attachments, (std::vector<std::string>{"calibration-generation-1.yaml", "calibration-generation-3.yaml"}));
  EXPECT_EQ(stats.attachments, 2u);
  EXPECT_EQ(metadata["steady_to_utc_offset_ns"], std::to_string(utc));
  EXPECT_EQ(metadata["arm"], "test arm");
  EXPECT_EQ(metadata["software"].rfind("telesphere ", 0), 0u);
  EXPECT_GT(utc, 1'700'000'000'000'000'000LL - 100'000'000'000'000LL) << "UTC minus an uptime";
  EXPECT_EQ(images, 40);
  EXPECT_EQ(decoded, static_cast<int>(stats.messages));
  McapSummary summary;
  ASSERT_TRUE(reader->summary(&summary, &error)) << error;
  EXPECT_EQ(summary.messages, stats.messages);
  EXPECT_EQ(summary.attachments, 2u);
  EXPECT_EQ(summary.metadata, 1u);
  EXPECT_GT(summary.start_ns, 1'700'000'000'000'000'000ULL) << "log times on UTC";
  EXPECT_EQ(summary.compressions, std::set<std::string>{"lz4"});
  std::filesystem::remove(path);
}

TEST(LinkRecorder, AFullQueueDropsAndCountsInsteadOfWaiting) {
  const std::string path = tempFile("full.mcap").string();
  std::string error;
  LinkRecorderOptions options;
  options.max_queue_bytes = 1;  // nothing fits: every message is dropped at once
  auto recorder = LinkRecorder::start(path, options, &error);
  ASSERT_TRUE(recorder) << error;
  proto::Envelope envelope;
  envelope.mutable_stereo_frame()->set_sequence(1);
  recorder->onLinkMessage(link::LinkTap::Direction::kSent, envelope, bytesOf(100, 1), bytesOf(100, 2));
  envelope.mutable_robot_state()->set_t_ns(1);
  recorder->onLinkMessage(link::LinkTap::Direction::kSent, envelope, nullptr, nullptr);
  envelope.mutable_ping();  // not recorded at all
  recorder->onLinkMessage(link::LinkTap::Direction::kReceived, envelope, nullptr, nullptr);
  EXPECT_FALSE(recorder->stop());  // not the whole session
  EXPECT_EQ(recorder->stats().dropped, 4u);  // three for the stereo frame, one state
  EXPECT_EQ(recorder->stats().messages, 0u);
  const auto reader = McapReader::open(path, &error);  // still a valid, empty recording
  ASSERT_TRUE(reader) << error;
  McapSummary summary;
  EXPECT_TRUE(reader->summary(&summary, &error)) << error;
  EXPECT_EQ(summary.messages, 0u);
  EXPECT_EQ(summary.channels.size(), recordedTopics().size());
  std::filesystem::remove(path);
}

// The reader's side of compressedImagePrefix: the JPEG found in place, in our prefix's field order
// and in protobuf's own, and nothing from bytes that are not a CompressedImage.
TEST(RecordingTopics, TheJpegOfACompressedImageIsFoundInPlace) {
  const std::string jpeg = "\xff\xd8 not really a jpeg \xff\xd9";
  const std::string ours = compressedImagePrefix(-1'500'000'001, "cam_l", jpeg.size()) + jpeg;
  foxglove::CompressedImage image;
  image.set_frame_id("cam_r");
  image.set_format("jpeg");
  image.set_data(jpeg);
  image.mutable_timestamp()->set_seconds(7);
  const std::string theirs = image.SerializeAsString();
  for (const std::string& bytes : {ours, theirs}) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data());
    const auto data = compressedImageData(p, bytes.size());
    ASSERT_TRUE(data);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(data->data()), data->size()), jpeg);
    EXPECT_GE(data->data(), p);  // a view into the message, not a copy
    EXPECT_LE(data->data() + data->size(), p + bytes.size());
    EXPECT_FALSE(compressedImageData(p, bytes.size() - 1));  // cut short
  }
  const std::string garbage = "\xff\xff\xff\xff\xff\xff";
  EXPECT_FALSE(compressedImageData(reinterpret_cast<const std::uint8_t*>(garbage.data()), garbage.size()));
  const auto none = compressedImageData(reinterpret_cast<const std::uint8_t*>(""), 0);
  ASSERT_TRUE(none);  // an empty message is a CompressedImage without data
  EXPECT_TRUE(none->empty());
}

TEST(LinkRecorder, ABadPathIsRefusedWithTheReason) {
  std::string error;
  EXPECT_FALSE(LinkRecorder::start("/nonexistent-dir/session.mcap", {}, &error));
  EXPECT_NE(error.find("/nonexistent-dir/session.mcap"), std::string::npos) << error;
}

}  // namespace
}  // namespace telesphere::record
