// SPDX-License-Identifier: MIT
/// @brief MediaSender and MediaReceiver on real UDP sockets on loopback, in real time: frames of
///        real JPEGs arrive byte-identical on a clean path; through the impairment relay (40 ms
///        RTT, 2 % loss, 20 Mbit/s) every delivered frame decodes, lost bands are filled and
///        counted, and the sender's rate follows the reports, not the source. A few seconds each.
#include <gtest/gtest.h>

#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "app/bench/impairment/udp_relay.h"
#include "robot/link/link_server.h"
#include "robot/link/media/media_receiver.h"
#include "robot/link/media/media_sender.h"
#include "tests/eventually.h"
#include "tests/robot/link/media_test_jpegs.h"

namespace telesphere::link::media {
namespace {

using namespace std::chrono_literals;

struct TestFrame {
  proto::StereoFrame stereo;
  std::vector<std::uint8_t> left, right;
};

TestFrame makeFrame(int width, int height, std::uint64_t sequence) {
  TestFrame f;
  const int seed = static_cast<int>(sequence) * 3;
  f.left = test::encodeJpeg(width, height, ChromaSubsampling::k420, 1, 85, seed);
  f.right = test::encodeJpeg(width, height, ChromaSubsampling::k420, 1, 85, seed + 1);
  f.stereo.set_sequence(sequence);
  for (auto* image : {f.stereo.mutable_left(), f.stereo.mutable_right()}) {
    image->set_width(static_cast<std::uint32_t>(width));
    image->set_height(static_cast<std::uint32_t>(height));
  }
  return f;
}

/// A receiver on loopback that `sender` has heard (null, with the reason as a failure, otherwise).
std::unique_ptr<MediaReceiver> listenTo(MediaSender& sender) {
  MediaReceiverOptions ro;
  ro.sender_port = sender.port();
  std::string error;
  auto receiver = MediaReceiver::start(ro, &error);
  EXPECT_TRUE(receiver) << error;
  if (!receiver) return nullptr;
  if (!telesphere::test::eventually([&] { return sender.hasReceiver(); }, 3000ms)) {
    ADD_FAILURE() << "no hello reached the sender";
    return nullptr;
  }
  return receiver;
}

/// Sends `frames` at `fps` while a consumer takes what the receiver hands over.
std::vector<AssembledFrame> run(MediaSender& sender, MediaReceiver& receiver, const std::vector<TestFrame>& frames,
                                double fps) {
  std::vector<AssembledFrame> got;
  std::atomic<bool> done{false};
  std::thread consumer([&] {
    while (!done) {
      if (auto f = receiver.waitNewest(20ms)) got.push_back(std::move(*f));
    }
    while (auto f = receiver.waitNewest(300ms)) got.push_back(std::move(*f));
  });
  auto next = std::chrono::steady_clock::now();
  for (const TestFrame& f : frames) {
    std::string error;
    EXPECT_TRUE(sender.sendFrame(f.stereo, f.left, f.right, &error)) << error;
    next += std::chrono::microseconds(static_cast<long>(1e6 / fps));
    std::this_thread::sleep_until(next);
  }
  done = true;
  consumer.join();
  return got;
}

TEST(MediaLoopback, TheRobotIsFoundByNameAndABadNameIsSaid) {
  MediaReceiverOptions ro;
  ro.sender_port = 9;  // nothing needs to listen: a UDP socket only connects
  ro.sender_address = "localhost";
  std::string error;
  EXPECT_TRUE(MediaReceiver::start(ro, &error)) << error;
  ro.sender_address = "";
  EXPECT_FALSE(MediaReceiver::start(ro, &error));
  EXPECT_NE(error.find("cannot resolve ''"), std::string::npos) << error;
  ro.sender_address = "127.0.0.1";
  ro.sender_port = 0;
  EXPECT_FALSE(MediaReceiver::start(ro, &error));
  EXPECT_EQ(error, "media receiver: no sender port");
}

TEST(MediaLoopback, FramesArriveByteIdenticalOnACleanPath) {
  std::string error;
  MediaSenderOptions so;
  so.bind_address = "127.0.0.1";
  so.rate.initial_bps = 40e6;
  auto sender = MediaSender::start(so, &error);
  ASSERT_TRUE(sender) << error;
  auto receiver = listenTo(*sender);
  ASSERT_TRUE(receiver);

  std::vector<TestFrame> frames;
  for (std::uint64_t i = 0; i < 20; ++i) frames.push_back(makeFrame(320, 240, i));
  const auto got = run(*sender, *receiver, frames, 20.0);
  ASSERT_GE(got.size(), 15u);
  for (const AssembledFrame& f : got) {
    ASSERT_LT(f.stereo.sequence(), frames.size());
    const TestFrame& sent = frames[f.stereo.sequence()];
    EXPECT_TRUE(f.whole());
    EXPECT_EQ(f.left_jpeg, sent.left);
    EXPECT_EQ(f.right_jpeg, sent.right);
  }
  const auto ss = sender->stats();
  const auto rs = receiver->stats();
  EXPECT_EQ(ss.frames_offered, 20u);
  EXPECT_EQ(ss.frames_sent + ss.frames_superseded, 20u);
  EXPECT_GT(ss.reports_received, 0u);
  EXPECT_GT(ss.rate.packets_reported, 0u);
  EXPECT_EQ(ss.rate.packets_lost, 0u);
  EXPECT_EQ(rs.assembler.frames_concealed, 0u);
  EXPECT_EQ(rs.assembler.frames_lost, 0u);
}

TEST(MediaLoopback, ThroughAnImpairedPathEveryDeliveredFrameDecodesAndTheRateFollowsThePath) {
  std::string error;
  MediaSenderOptions so;
  so.bind_address = "127.0.0.1";
  so.rate.initial_bps = 8e6;
  auto sender = MediaSender::start(so, &error);
  ASSERT_TRUE(sender) << error;
  bench::impairment::UdpRelayOptions relay_options;
  relay_options.server_port = sender->port();
  for (auto* path : {&relay_options.to_server, &relay_options.to_client}) {
    path->one_way_delay_ns = 20'000'000;
    path->jitter_ns = 2'000'000;
  }
  relay_options.to_client.loss.loss_fraction = 0.02;
  relay_options.to_client.loss.seed = 11;
  relay_options.to_client.rate = bench::impairment::RateTrace::constant(20e6);
  relay_options.to_client.queue_limit_bytes = 256 << 10;
  auto relay = bench::impairment::UdpRelay::start(relay_options, &error);
  ASSERT_TRUE(relay) << error;
  MediaReceiverOptions ro;
  ro.sender_port = relay->port();
  auto receiver = MediaReceiver::start(ro, &error);
  ASSERT_TRUE(receiver) << error;
  ASSERT_TRUE(telesphere::test::eventually([&] { return sender->hasReceiver(); }, 3000ms)) << "no hello reached the sender";

  // 640×480 frames at 30 Hz: about 2 × 45 KB a frame, 22 Mbit/s offered: more than the path.
  std::vector<TestFrame> frames;
  for (std::uint64_t i = 0; i < 8; ++i) frames.push_back(makeFrame(640, 480, i));
  std::vector<TestFrame> schedule;
  for (std::uint64_t i = 0; i < 90; ++i) {
    TestFrame f = frames[i % frames.size()];
    f.stereo.set_sequence(i);
    schedule.push_back(std::move(f));
  }
  const auto got = run(*sender, *receiver, schedule, 30.0);
  ASSERT_GE(got.size(), 20u);
  std::size_t filled = 0;
  for (const AssembledFrame& f : got) {
    const TestFrame& sent = frames[f.stereo.sequence() % frames.size()];
    const test::Planes l = test::decodePlanes(f.left_jpeg), r = test::decodePlanes(f.right_jpeg);
    ASSERT_TRUE(l.ok && r.ok) << "frame " << f.stereo.sequence() << " does not decode";
    if (!f.whole()) ++filled;
    if (f.left_lost.empty()) {
      EXPECT_EQ(f.left_jpeg, sent.left);
    }
  }
  const auto ss = sender->stats();
  const auto rs = receiver->stats();
  const auto relay_stats = relay->stats();
  std::printf("impaired loopback: %zu of 90 frames shown, %zu with filled bands, %llu bands, %llu chunks rebuilt; sender: %llu superseded, "
              "target %.1f Mbit/s, delivered %.1f Mbit/s, loss %.3f; relay: %llu lost, %llu dropped at the queue\n",
              got.size(), filled, static_cast<unsigned long long>(rs.assembler.bands_lost),
              static_cast<unsigned long long>(rs.assembler.chunks_recovered),
              static_cast<unsigned long long>(ss.frames_superseded), ss.rate.target_bps * 1e-6,
              ss.rate.delivered_bps * 1e-6, ss.rate.loss_fraction,
              static_cast<unsigned long long>(relay_stats.to_client.lost),
              static_cast<unsigned long long>(relay_stats.to_client.dropped_queue));
  EXPECT_GT(rs.assembler.chunks_recovered, 0u) << "2 % loss over ~80 datagrams a frame: parity rebuilds chunks";
  EXPECT_LT(filled, got.size() / 4) << "with 10 % parity, few frames keep a lost band";
  EXPECT_EQ(rs.assembler.frames_malformed, 0u);
  EXPECT_GT(ss.frames_superseded, 0u) << "22 Mbit/s offered to a 20 Mbit/s path: the sender drops its own frames";
  EXPECT_LT(ss.rate.target_bps, 1.5 * 20e6) << "the target must follow the path, not the source";
  EXPECT_GT(ss.rate.packets_lost, 0u);
}

/// Frames whole, and the counts, of 40 frames at 10 Hz through 20 ms RTT and 5 % loss, parity
/// off, with retransmission on or off.
struct RepairRun {
  std::size_t delivered = 0, whole = 0;
  MediaSenderStats sender;
  MediaReceiverStats receiver;
};

RepairRun runRepair(bool repair) {
  RepairRun out;
  std::string error;
  MediaSenderOptions so;
  so.bind_address = "127.0.0.1";
  so.packetizer.fec_overhead = 0;  // only retransmission repairs here
  so.packetizer.repeat_headers = false;
  auto sender = MediaSender::start(so, &error);
  EXPECT_TRUE(sender) << error;
  if (!sender) return out;
  bench::impairment::UdpRelayOptions relay_options;
  relay_options.server_port = sender->port();
  for (auto* path : {&relay_options.to_server, &relay_options.to_client}) path->one_way_delay_ns = 10'000'000;
  relay_options.to_client.loss.loss_fraction = 0.05;
  relay_options.to_client.loss.seed = 21;
  auto relay = bench::impairment::UdpRelay::start(relay_options, &error);
  EXPECT_TRUE(relay) << error;
  MediaReceiverOptions ro;
  ro.sender_port = relay->port();
  ro.assembler.repair = repair;
  auto receiver = MediaReceiver::start(ro, &error);
  EXPECT_TRUE(receiver) << error;
  EXPECT_TRUE(telesphere::test::eventually([&] { return sender->hasReceiver(); }, 3000ms));
  std::vector<TestFrame> schedule;
  for (std::uint64_t i = 0; i < 40; ++i) schedule.push_back(makeFrame(640, 480, i % 4));
  for (std::uint64_t i = 0; i < 40; ++i) schedule[i].stereo.set_sequence(i);
  const auto got = run(*sender, *receiver, schedule, 10.0);
  out.delivered = got.size();
  for (const AssembledFrame& f : got) {
    out.whole += f.whole();
    EXPECT_TRUE(test::decodePlanes(f.left_jpeg).ok && test::decodePlanes(f.right_jpeg).ok);
  }
  out.sender = sender->stats();
  out.receiver = receiver->stats();
  return out;
}

/// An H.264 stereo frame of `bytes` per image (the framing never parses an access unit).
TestFrame videoFrame(std::uint64_t sequence, bool key, std::size_t bytes) {
  TestFrame f;
  f.left.assign(bytes, static_cast<std::uint8_t>(sequence));
  f.right.assign(bytes, static_cast<std::uint8_t>(sequence + 100));
  f.stereo.set_sequence(sequence);
  for (auto* image : {f.stereo.mutable_left(), f.stereo.mutable_right()}) {
    image->set_width(320);
    image->set_height(240);
    image->set_codec(proto::VIDEO_CODEC_H264);
    image->set_key_frame(key);
  }
  return f;
}

// H.264/HEVC (#34): each frame is predicted from the one before, so the sender queues them
// instead of letting a newer one replace a waiting one; past the queue's bound it drops what
// waits, refuses predicted frames until a key frame and asks its encoder for one. A new
// receiver is asked for too. The receiver never gets a predicted frame whose reference it missed.
TEST(MediaLoopback, PredictedFramesQueueAndAnOverflowRestartsTheStreamAtAKeyFrame) {
  std::string error;
  MediaSenderOptions so;
  so.bind_address = "127.0.0.1";
  so.rate.initial_bps = 1e6;  // 2 × 6 kB take about 80 ms a frame at 1.25 × 1 Mbit/s
  so.rate.min_bps = 1e6;
  so.rate.max_bps = 1e6;
  so.max_video_frames_waiting = 3;
  auto sender = MediaSender::start(so, &error);
  ASSERT_TRUE(sender) << error;
  auto receiver = listenTo(*sender);
  ASSERT_TRUE(receiver);
  EXPECT_TRUE(sender->takeKeyFrameRequest()) << "a new receiver starts at a key frame";
  EXPECT_FALSE(sender->takeKeyFrameRequest()) << "asked once";

  std::vector<std::uint64_t> got;
  std::mutex got_mutex;
  std::atomic<bool> done{false};
  std::thread consumer([&] {
    while (!done) {
      if (auto f = receiver->waitNewest(20ms)) {
        std::lock_guard lock(got_mutex);
        got.push_back(f->stereo.sequence());
      }
    }
  });
  // A predicted frame before any key frame is useless to the receiver: refused.
  const auto offer = [&](const TestFrame& f) { EXPECT_TRUE(sender->sendFrame(f.stereo, f.left, f.right, &error)) << error; };
  offer(videoFrame(1, false, 6000));
  // A key frame, then 8 predicted ones at once: the key frame goes, 3 wait, the 4th overflows.
  offer(videoFrame(2, true, 6000));
  std::this_thread::sleep_for(5ms);  // the pacer has begun the key frame
  for (std::uint64_t s = 3; s <= 10; ++s) offer(videoFrame(s, false, 6000));
  EXPECT_TRUE(sender->takeKeyFrameRequest()) << "the overflow asks the encoder for a key frame";
  auto stats = sender->stats();
  EXPECT_EQ(stats.frames_superseded, 3u) << "what waited (3, 4, 5) is dropped with the chain";
  EXPECT_EQ(stats.video_frames_waiting_for_key, 1u + 5u) << "1, and 6 to 10 after the overflow";
  // The encoder's key frame restarts the stream; the frames after it go in order.
  offer(videoFrame(11, true, 6000));
  offer(videoFrame(12, false, 6000));
  offer(videoFrame(13, false, 6000));
  ASSERT_TRUE(telesphere::test::eventually([&] { return sender->stats().frames_sent >= 4; }, 3000ms));
  std::this_thread::sleep_for(200ms);
  done = true;
  consumer.join();
  stats = sender->stats();
  EXPECT_EQ(stats.frames_sent, 4u) << "2, 11, 12, 13";
  EXPECT_EQ(stats.video_key_frames_asked, 2u);
  const std::set<std::uint64_t> received(got.begin(), got.end());
  for (const std::uint64_t s : received) EXPECT_TRUE(s == 2 || s >= 11) << "frame " << s << " reached the receiver";
  EXPECT_TRUE(received.count(13)) << "the stream went on after its key frame";
  EXPECT_FALSE(sender->takeKeyFrameRequest()) << "nothing broke the chain since";
}

TEST(MediaLoopback, RetransmissionRepairsWhatParityCannotWhileTheFrameIsStillDue) {
  // 10 Hz, 20 ms RTT: a repair arrives long before the next frame. Without parity a 640×480
  // stereo frame (~65 datagrams) at 5 % loss is rarely whole; asked for again, nearly always.
  const RepairRun off = runRepair(false), on = runRepair(true);
  std::printf("5 %% loss, 20 ms RTT, 10 Hz, no parity: whole %zu of %zu without retransmission, %zu of %zu with "
              "(%llu chunks asked for, %llu resent, %llu arrived after asking, %llu requests refused of %llu, "
              "round trip %.1f ms)\n",
              off.whole, off.delivered, on.whole, on.delivered,
              static_cast<unsigned long long>(on.receiver.assembler.chunks_requested),
              static_cast<unsigned long long>(on.sender.chunks_resent),
              static_cast<unsigned long long>(on.receiver.assembler.chunks_repaired),
              static_cast<unsigned long long>(on.sender.repair_requests_refused),
              static_cast<unsigned long long>(on.sender.repair_requests), on.receiver.assembler.repair_rtt_ms);
  ASSERT_GE(off.delivered, 30u);
  ASSERT_GE(on.delivered, 30u);
  EXPECT_EQ(off.receiver.assembler.chunks_requested, 0u);
  EXPECT_EQ(off.sender.chunks_resent, 0u);
  EXPECT_GT(on.receiver.assembler.chunks_repaired, 0u);
  EXPECT_GT(on.sender.chunks_resent, 0u);
  EXPECT_LE(on.sender.repair_requests_refused * 4, on.sender.repair_requests)
      << "most frames are still the newest when asked for (a second round may come after the next began)";
  EXPECT_GE(on.whole * 10, on.delivered * 6) << "retransmitted: at least 60 % whole";
  EXPECT_LE(off.whole * 4, off.delivered) << "without: fewer than a quarter";
}

TEST(MediaLoopback, HeadTargetsGetThroughA30PercentLossThanksToTheirRepeats) {
  // 120 targets at 90 Hz through a path that loses 30 % of the operator's datagrams: a target is
  // lost only with the two datagrams after it (0.3³ = 2.7 %); the robot's LinkServer keeps the newest.
  std::string error;
  link::LinkEndpoints endpoints;
  endpoints.base_port = 28210;
  LinkServer server(endpoints);
  std::mutex mutex;
  std::set<std::int64_t> stamps;
  MediaSenderOptions so;
  so.bind_address = "127.0.0.1";
  so.on_head_target = [&](const proto::HeadTarget& t) {
    server.offerHeadTarget(t);
    std::lock_guard lock(mutex);
    stamps.insert(t.t_ns());
  };
  auto sender = MediaSender::start(so, &error);
  ASSERT_TRUE(sender) << error;
  bench::impairment::UdpRelayOptions relay_options;
  relay_options.server_port = sender->port();
  relay_options.to_server.loss.loss_fraction = 0.3;
  relay_options.to_server.loss.seed = 9;
  auto relay = bench::impairment::UdpRelay::start(relay_options, &error);
  ASSERT_TRUE(relay) << error;
  MediaReceiverOptions ro;
  ro.sender_port = relay->port();
  auto receiver = MediaReceiver::start(ro, &error);
  ASSERT_TRUE(receiver) << error;
  for (int i = 1; i <= 120; ++i) {
    proto::HeadTarget t;
    t.set_t_ns(i);
    t.set_sender_instance(5);
    t.set_valid(true);
    receiver->sendHeadTarget(t);
    std::this_thread::sleep_for(11ms);
  }
  // Quiet for 300 ms: everything that will arrive has.
  std::size_t seen = 0;
  for (int quiet_ms = 0; quiet_ms < 300; quiet_ms += 20) {
    std::this_thread::sleep_for(20ms);
    std::lock_guard lock(mutex);
    if (stamps.size() != seen) quiet_ms = 0;
    seen = stamps.size();
  }
  std::lock_guard lock(mutex);
  std::printf("head targets: %zu of 120 reached the robot through 30 %% loss\n", stamps.size());
  EXPECT_GE(stamps.size(), 100u) << "without the repeats about 84 of 120 would arrive";
  ASSERT_TRUE(server.latestHeadTarget());
  // The newest kept is among the last few sent (losing six datagrams in a row: 0.07 %).
  EXPECT_GE(server.latestHeadTarget()->t_ns(), 115) << "the newest, not a repeat of an older one";
  proto::HeadTarget old;
  old.set_t_ns(3);
  old.set_sender_instance(5);
  EXPECT_FALSE(server.offerHeadTarget(old)) << "an older target of the same sender is refused";
  EXPECT_GT(sender->stats().head_target_datagrams, 60u);
}

}  // namespace
}  // namespace telesphere::link::media
