// SPDX-License-Identifier: MIT
/// @brief H.264 and HEVC over the real link (#34): the robot's StereoAvEncoder → LinkServer →
///        loopback → LinkClient → StereoFrameDecoder, whose pool decodes each camera's frames in
///        the order they came. Every frame decodes close to its source (PSNR); a frame the link
///        lost makes the decoder refuse the frames after it (counted "awaiting_key_frame") and ask
///        the robot for a key frame over the control channel, and the picture comes back with the
///        key frame the encoder then sends; a decoder joining part way asks for one too; frames
///        whose two cameras name different codecs are refused as unsupported.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

#include "robot/clock/clock.h"
#include "robot/link/link_client.h"
#include "robot/link/link_server.h"
#include "robot/link/proto_enums.h"
#include "robot/video/frame_to_yuv420.h"
#include "robot/video/stereo_av_encoder.h"
#include "tests/eventually.h"
#include "xr/video/stereo_frame_decoder.h"

namespace telesphere::xr {
namespace {

using namespace std::chrono_literals;
using link::VideoCodec;

constexpr int kWidth = 128, kHeight = 96;

/// Camera image `t` of a smooth scene panning 2 px an image (RGB).
robot::cameras::CameraFrame sceneImage(int t, int camera) {
  robot::cameras::CameraFrame f;
  f.format = robot::cameras::PixelFormat::kRgb8;
  f.width = kWidth;
  f.height = kHeight;
  f.stride_bytes = kWidth * 3;
  f.sequence = static_cast<std::uint64_t>(t);
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(static_cast<std::size_t>(kWidth) * kHeight * 3);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      std::uint8_t* p = pixels->data() + (static_cast<std::size_t>(y) * kWidth + x) * 3;
      const int u = x + 2 * t + 9 * camera;
      p[0] = static_cast<std::uint8_t>(128 + 80 * std::sin(0.09 * u));
      p[1] = static_cast<std::uint8_t>(128 + 80 * std::cos(0.06 * y + 0.02 * u));
      p[2] = static_cast<std::uint8_t>(((u / 8 + y / 8) % 2) ? 200 : 60);
    }
  f.pixels = std::move(pixels);
  return f;
}

double psnrY(const render::YuvPlanes& decoded, const robot::cameras::Yuv420Image& source) {
  const auto y = decoded.yPlane();
  double sum = 0;
  for (std::size_t i = 0; i < source.y.size(); ++i) {
    const double d = double(y[i]) - double(source.y[i]);
    sum += d * d;
  }
  const double mse = sum / double(source.y.size());
  return mse == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 / mse);
}

struct Rig {
  static link::LinkEndpoints endpoints(int n) {
    link::LinkEndpoints e;
    e.base_port = 29100 + 8 * n;  // four ports each; nothing else in the tests uses 29100-29199
    return e;
  }

  Rig(int n, VideoCodec codec)
      : server(endpoints(n)), client(endpoints(n)), encoder(clock, options(codec)), decoder(client, decoderOptions()) {
    server.setControlHandler([this](const link::proto::ControlRequest& request) {
      link::proto::ControlReply reply;
      reply.set_id(request.id());
      if (request.has_request_key_frame()) {
        ++key_frame_requests;
        encoder.requestKeyFrame();
        reply.set_ok(true);
      }
      return reply;
    });
  }

  static robot::video::StereoAvEncoderOptions options(VideoCodec codec) {
    robot::video::StereoAvEncoderOptions o;
    o.codec = codec;
    o.bit_rate_bps = 6'000'000;
    o.fps = 30;
    o.key_frame_interval = 1000;  // only the first and the requested ones
    return o;
  }
  static video::StereoFrameDecoder::Options decoderOptions() {
    video::StereoFrameDecoder::Options o;
    o.threads = 4;  // pairs decode two at a time: the tickets keep each camera's order
    o.pairs_in_flight = 2;
    return o;
  }

  /// Encodes image t of both cameras (always, so the encoder's chain goes on) and publishes it
  /// unless `lose`; the sequence counts every frame encoded, as the robot's does.
  void send(int t, bool lose = false) {
    robot::video::EncodedAccessUnitPair pair;
    std::string error;
    ASSERT_TRUE(encoder.encode(sceneImage(t, 0), sceneImage(t, 1), pair, &error)) << error;
    link::proto::StereoFrame f;
    f.set_sequence(++sequence);
    for (auto* image : {f.mutable_left(), f.mutable_right()}) {
      image->set_width(kWidth);
      image->set_height(kHeight);
      image->set_codec(link::toProto(encoder.options().codec));
      image->set_key_frame(pair.key_frame);
      image->set_capture_ns(link::linkNowNs());
    }
    last_key = pair.key_frame;
    if (!lose) server.publishStereoFrame(f, pair.left.bytes, pair.right.bytes);
  }

  /// Sends images until one comes out decoded (a PUB drops what it sends before the SUB joined).
  std::shared_ptr<const video::DecodedStereoFrame> connect(int& t) {
    for (int i = 0; i < 300; ++i) {
      send(t++);
      if (auto f = decoder.waitNewer(0, 30ms)) return f;
    }
    return nullptr;
  }

  robot::clock::SteadyClock clock;
  link::LinkServer server;
  link::LinkClient client;
  robot::video::StereoAvEncoder encoder;
  video::StereoFrameDecoder decoder;
  std::uint64_t sequence = 0;
  bool last_key = false;
  std::atomic<int> key_frame_requests{0};
};

class VideoStreamLink : public ::testing::TestWithParam<VideoCodec> {};

TEST_P(VideoStreamLink, EveryFrameInOrderCloseToItsSource) {
  Rig rig(GetParam() == VideoCodec::kH264 ? 0 : 1, GetParam());
  int t = 0;
  ASSERT_TRUE(rig.connect(t));
  robot::video::FrameToYuv420 to_planes;
  robot::cameras::Yuv420Image source[2];
  for (int i = 0; i < 20; ++i) {
    rig.send(t);
    const auto f = rig.decoder.waitNewer(rig.sequence - 1, 2s);
    ASSERT_TRUE(f) << "frame " << rig.sequence << " did not come out";
    ASSERT_EQ(f->frame.sequence(), rig.sequence);
    std::string error;
    ASSERT_TRUE(to_planes.convert(sceneImage(t, 0), source[0], &error)) << error;
    ASSERT_TRUE(to_planes.convert(sceneImage(t, 1), source[1], &error)) << error;
    EXPECT_GT(psnrY(*f->left, source[0]), 30.0) << "frame " << t;
    EXPECT_GT(psnrY(*f->right, source[1]), 30.0) << "frame " << t;
    EXPECT_LT(psnrY(*f->left, source[1]), psnrY(*f->left, source[0]));  // the left camera's, not the right's
    ++t;
  }
  const auto s = rig.decoder.stats();
  EXPECT_EQ(s.codec, link::videoCodecName(GetParam()));
  EXPECT_EQ(s.dropped(video::FrameDropReason::kCorrupt), 0u);
  EXPECT_EQ(s.dropped(video::FrameDropReason::kAwaitingKeyFrame), 0u);
}

TEST_P(VideoStreamLink, ALostFrameAsksForAKeyFrameAndThePictureComesBack) {
  Rig rig(GetParam() == VideoCodec::kH264 ? 2 : 3, GetParam());
  int t = 0;
  ASSERT_TRUE(rig.connect(t));
  for (int i = 0; i < 3; ++i) {
    rig.send(t++);
    ASSERT_TRUE(rig.decoder.waitNewer(rig.sequence - 1, 2s));
  }
  const int requests_before = rig.key_frame_requests.load();
  const std::uint64_t shown_before = rig.decoder.stats().decoded;
  rig.send(t++, /*lose=*/true);
  // The frames after the loss are refused until the key frame the decoder asked for comes.
  std::shared_ptr<const video::DecodedStereoFrame> back;
  std::uint64_t sent_before_key = 0;
  for (int i = 0; i < 200 && !back; ++i) {
    rig.send(t++);
    if (!rig.last_key) ++sent_before_key;
    back = rig.decoder.waitNewer(rig.sequence - 1, 50ms);
  }
  ASSERT_TRUE(back) << "the picture never came back";
  EXPECT_TRUE(back->frame.left().key_frame()) << "the first frame shown after a loss is a key frame";
  EXPECT_GT(rig.key_frame_requests.load(), requests_before);
  const auto s = rig.decoder.stats();
  EXPECT_GE(s.key_frames_requested, 1u);
  EXPECT_GE(s.dropped(video::FrameDropReason::kAwaitingKeyFrame), 1u);
  EXPECT_EQ(s.dropped(video::FrameDropReason::kCorrupt), 0u) << "nothing smeared went to the renderer";
  EXPECT_GE(sent_before_key, 1u);
  EXPECT_GT(s.decoded, shown_before);
  // And on from there.
  rig.send(t++);
  EXPECT_TRUE(rig.decoder.waitNewer(rig.sequence - 1, 2s));
}

TEST_P(VideoStreamLink, ADecoderJoiningPartWayAsksForAKeyFrame) {
  Rig rig(GetParam() == VideoCodec::kH264 ? 4 : 5, GetParam());
  int t = 0;
  // The first pair (a key frame) is lost; the decoder's first frame is predicted.
  rig.send(t++, /*lose=*/true);
  ASSERT_TRUE(rig.connect(t));
  EXPECT_GE(rig.key_frame_requests.load(), 1);
  EXPECT_TRUE(rig.decoder.newest()->frame.left().key_frame());
}

TEST(VideoStreamLinkRefusals, TwoCodecsInOnePairAreRefusedAsUnsupported) {
  Rig rig(6, VideoCodec::kH264);
  int t = 0;
  ASSERT_TRUE(rig.connect(t));
  const auto before = rig.decoder.stats().dropped(video::FrameDropReason::kUnsupported);
  link::proto::StereoFrame f;
  f.set_sequence(++rig.sequence);
  for (auto* image : {f.mutable_left(), f.mutable_right()}) {
    image->set_width(kWidth);
    image->set_height(kHeight);
  }
  f.mutable_left()->set_codec(link::proto::VIDEO_CODEC_H264);
  f.mutable_right()->set_codec(link::proto::VIDEO_CODEC_HEVC);
  const auto bytes = std::make_shared<const std::vector<std::uint8_t>>(100, 0);
  ASSERT_TRUE(test::eventually([&] {
    rig.server.publishStereoFrame(f, bytes, bytes);
    return rig.decoder.stats().dropped(video::FrameDropReason::kUnsupported) > before;
  }));
}

INSTANTIATE_TEST_SUITE_P(Codecs, VideoStreamLink, ::testing::Values(VideoCodec::kH264, VideoCodec::kHevc),
                         [](const auto& info) { return std::string(link::videoCodecName(info.param)); });

}  // namespace
}  // namespace telesphere::xr
