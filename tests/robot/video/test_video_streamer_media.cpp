// SPDX-License-Identifier: MIT
/// @brief VideoStreamer on the media path, in real time on loopback: replay cameras at 30 Hz →
///        pairs → VideoStreamer → MediaSender (capped at 1 Mbit/s by the supervisor) →
///        MediaReceiver. The stream gives up frame rate, then scale, to fit; the frames that
///        arrive are smaller, decode, and together stay near the cap; without a receiver the
///        stream stays nominal. H.264 (#34) keeps frame rate and size and lowers the encoder's
///        rate instead; every frame arrives in order, the first a key frame. About 10 s.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cmath>
#include <thread>

#include "robot/cameras/replay_camera.h"
#include "robot/clock/clock.h"
#include "robot/link/link_server.h"
#include "robot/link/proto_enums.h"
#include "robot/link/media/media_receiver.h"
#include "robot/link/media/media_sender.h"
#include "robot/video/video_streamer.h"
#include "tests/eventually.h"
#include "tests/support/smooth_camera_frame.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;

using telesphere::test::smoothFrame;

cameras::ReplayCameraConfig camera(const char* name) {
  cameras::ReplayCameraConfig c;
  c.name = name;
  c.fps = 30;
  return c;
}

struct MediaRig {
  MediaRig(int port, double cap_bps, link::VideoCodec codec = link::VideoCodec::kMjpeg)
      : server(endpoints(port)),
        left(clock, {smoothFrame(640, 360, 0.0)}, camera("left")),
        right(clock, {smoothFrame(640, 360, 1.0)}, camera("right")),
        pairs(left, right, stereo::StereoPairerOptions{.tolerance_ns = 5'000'000}) {
    link::media::MediaSenderOptions options;
    options.bind_address = "127.0.0.1";
    options.port = static_cast<std::uint16_t>(port + link::LinkEndpoints::kMedia);
    std::string error;
    media = link::media::MediaSender::start(options, &error);
    EXPECT_TRUE(media) << error;
    if (cap_bps > 0) media->setCapBps(cap_bps);
    video::VideoStreamerConfig config;
    config.media = media.get();
    config.adaptive.nominal_fps = 30;
    config.codec = codec;
    config.video.fps = 30;
    config.video.bit_rate_bps = 8'000'000;
    streamer = std::make_unique<video::VideoStreamer>(pairs, server, clock, nullptr, config);
    left.start(&error);
    right.start(&error);
    pairs.start();
    streamer->start();
  }
  ~MediaRig() {
    streamer->stop();
    pairs.stop();
    left.stop();
    right.stop();
  }
  /// A receiver on the rig's media path, once the sender has heard it (null, with a failure, if not).
  std::unique_ptr<link::media::MediaReceiver> listen(int port) {
    link::media::MediaReceiverOptions options;
    options.sender_port = static_cast<std::uint16_t>(port + link::LinkEndpoints::kMedia);
    std::string error;
    auto receiver = link::media::MediaReceiver::start(options, &error);
    EXPECT_TRUE(receiver) << error;
    if (!receiver || !telesphere::test::eventually([&] { return media->hasReceiver(); }, 3000ms)) {
      ADD_FAILURE() << "the media sender never heard the receiver";
      return nullptr;
    }
    return receiver;
  }
  static link::LinkEndpoints endpoints(int port) {
    link::LinkEndpoints e;
    e.base_port = port;
    return e;
  }

  clock::SteadyClock clock;
  link::LinkServer server;
  cameras::ReplayCamera left, right;
  stereo::StereoPairSource pairs;
  std::unique_ptr<link::media::MediaSender> media;
  std::unique_ptr<video::VideoStreamer> streamer;
};

/// Every frame `receiver` hands over in the next `duration`.
std::vector<link::media::AssembledFrame> framesFor(link::media::MediaReceiver& receiver,
                                                   std::chrono::milliseconds duration) {
  std::vector<link::media::AssembledFrame> got;
  const auto end = std::chrono::steady_clock::now() + duration;
  while (std::chrono::steady_clock::now() < end)
    if (auto f = receiver.waitNewest(50ms)) got.push_back(std::move(*f));
  return got;
}

TEST(VideoStreamerMedia, WithoutAReceiverTheStreamStaysNominalButCarriesRestartMarkers) {
  MediaRig rig(27410, 0);
  ASSERT_TRUE(telesphere::test::eventually([&] { return rig.streamer->stats().frames_sent >= 10; }, 5000ms));
  const auto s = rig.streamer->stats();
  EXPECT_FALSE(s.stream_adapted);
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.frames_skipped_for_rate, 0u);
  EXPECT_GT(rig.media->stats().frames_without_receiver, 0u);
}

TEST(VideoStreamerMedia, ACapOfOneMegabitGivesUpFrameRateThenScaleAndTheFramesStillDecode) {
  MediaRig rig(27420, 1e6);
  auto receiver = rig.listen(27420);
  ASSERT_TRUE(receiver);
  // Two seconds to settle, then three measured.
  std::this_thread::sleep_for(2s);
  const auto before = rig.media->stats();
  const std::vector<link::media::AssembledFrame> got = framesFor(*receiver, 3s);
  const auto after = rig.media->stats();
  const auto s = rig.streamer->stats();
  const double mbit_per_s = 8.0 * static_cast<double>(after.bytes_sent - before.bytes_sent) / 3.0 * 1e-6;
  std::printf("cap 1 Mbit/s: %.2f Mbit/s sent, stream %.1f Hz, scale %.2f, q%d (%s), %zu frames in 3 s\n", mbit_per_s,
              s.stream.fps, s.stream.scale, s.stream.quality, video::streamLimitedByName(s.stream.limited_by), got.size());
  EXPECT_TRUE(s.stream_adapted);
  EXPECT_LT(s.stream.scale, 1.0) << "15 Hz of 640x360 stereo at q90 is about 7 Mbit/s: the scale must go";
  EXPECT_GT(s.frames_skipped_for_rate, 0u);
  EXPECT_LT(mbit_per_s, 1.15) << "the framing's own bytes count against the cap too";
  ASSERT_GE(got.size(), 20u);
  tjhandle d = tjInitDecompress();
  for (const auto& f : got) {
    int w = 0, h = 0, samp = 0, cs = 0;
    ASSERT_EQ(tjDecompressHeader3(d, f.left_jpeg.data(), f.left_jpeg.size(), &w, &h, &samp, &cs), 0);
    EXPECT_LT(w, 640);
    EXPECT_EQ(static_cast<std::uint32_t>(w), f.stereo.left().width()) << "the message says the scaled size";
  }
  tjDestroy(d);
}

TEST(VideoStreamerMedia, H264UnderACapLowersTheEncodersRateAndKeepsEveryFrameInOrder) {
  MediaRig rig(27430, 1e6, link::VideoCodec::kH264);
  auto receiver = rig.listen(27430);
  ASSERT_TRUE(receiver);
  const auto settling = framesFor(*receiver, 2s);
  ASSERT_FALSE(settling.empty()) << "nothing arrived while settling";
  EXPECT_TRUE(settling.front().stereo.left().key_frame()) << "a new receiver's first frame is a key frame";
  const auto before = rig.media->stats();
  const std::vector<link::media::AssembledFrame> got = framesFor(*receiver, 3s);
  const auto after = rig.media->stats();
  const auto s = rig.streamer->stats();
  const double mbit_per_s = 8.0 * static_cast<double>(after.bytes_sent - before.bytes_sent) / 3.0 * 1e-6;
  std::printf("H.264 capped at 1 Mbit/s: %.2f Mbit/s sent, encoder at %.2f Mbit/s (%s), %zu frames in 3 s, "
              "%llu waited for a key frame\n",
              mbit_per_s, static_cast<double>(s.video.bit_rate_bps) * 1e-6, video::streamLimitedByName(s.stream.limited_by),
              got.size(), static_cast<unsigned long long>(after.video_frames_waiting_for_key));
  EXPECT_EQ(s.stream.limited_by, video::StreamLimitedBy::kBitRate);
  EXPECT_LE(static_cast<double>(s.video.bit_rate_bps), 0.9 * 1e6) << "the encoder aims under the cap's budget";
  EXPECT_GE(static_cast<double>(s.video.bit_rate_bps), video::VideoStreamer::kMinVideoBitRateBps);
  EXPECT_EQ(s.frames_skipped_for_rate, 0u) << "H.264 keeps the frame rate";
  EXPECT_EQ(s.width, 640) << "and the size";
  EXPECT_LT(mbit_per_s, 1.15);
  ASSERT_GE(got.size(), 45u) << "30 Hz for 3 s, the receiver's hand-over latest-wins";
  std::uint64_t gaps = 0;
  for (std::size_t i = 1; i < got.size(); ++i) {
    EXPECT_TRUE(got[i].whole());
    EXPECT_EQ(got[i].stereo.left().codec(), link::proto::VIDEO_CODEC_H264);
    if (got[i].stereo.sequence() != got[i - 1].stereo.sequence() + 1) ++gaps;
  }
  EXPECT_EQ(after.frames_superseded - before.frames_superseded, 0u) << "no predicted frame dropped at the sender";
  EXPECT_LE(gaps, 2u) << "frames skipped between the receiver and this test's reads";
}

}  // namespace
}  // namespace telesphere::robot
