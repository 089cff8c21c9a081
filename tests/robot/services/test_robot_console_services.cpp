// SPDX-License-Identifier: MIT
/// @brief What the robot serves the console, on a real link over loopback with replay cameras:
///        the preview stream (reduction exact against a reference, JPEGs that decode to it), the
///        sent-frame telemetry of the video path, JPEG quality changed through a control request
///        (and every reply carrying the settings in force), and the health report.
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cmath>
#include <limits>
#include <random>
#include <thread>

#include "robot/arm/head_arm_sim.h"
#include "robot/link/link_client.h"
#include "robot/link/media/media_receiver.h"
#include "robot/link/media/media_sender.h"
#include "robot/video/preview_streamer.h"
#include "robot/cameras/replay_camera.h"
#include "robot/cameras/debayer.h"
#include "robot/services/robot_control.h"
#include "robot/services/robot_health_reporter.h"
#include "robot/clock/sim_clock.h"
#include "robot/video/video_streamer.h"
#include "tests/eventually.h"
#include "tests/support/smooth_camera_frame.h"

namespace telesphere::robot {
namespace {

using namespace std::chrono_literals;
using ::telesphere::test::eventually;

cameras::CameraFrame randomFrame(int w, int h, cameras::PixelFormat format, std::uint64_t seed) {
  cameras::CameraFrame f;
  f.width = w;
  f.height = h;
  f.format = format;
  const int channels = cameras::bytesPerPixel(format);
  f.stride_bytes = w * channels + 5;  // padded rows
  auto pixels = std::make_shared<std::vector<std::uint8_t>>(std::size_t(f.stride_bytes) * std::size_t(h));
  std::mt19937_64 rng(seed);
  for (auto& p : *pixels) p = std::uint8_t(rng());
  f.pixels = pixels;
  return f;
}

TEST(PreviewReduction, IsTheRoundedBlockMeanAndRefusesWhatItCannotReduce) {
  for (cameras::PixelFormat format : {cameras::PixelFormat::kRgb8, cameras::PixelFormat::kMono8}) {
    const cameras::CameraFrame f = randomFrame(1003, 517, format, 3);
    const auto img = video::reduceForPreview(f, 320);
    ASSERT_TRUE(img);
    const int k = 4;  // ceil(1003 / 320)
    EXPECT_EQ(img->width, 1003 / k);
    EXPECT_EQ(img->height, 517 / k);
    const int c = cameras::bytesPerPixel(format);
    EXPECT_EQ(img->channels, c);
    for (int y = 0; y < img->height; y += 7)
      for (int x = 0; x < img->width; x += 11)
        for (int ch = 0; ch < c; ++ch) {
          unsigned sum = 0;
          for (int dy = 0; dy < k; ++dy)
            for (int dx = 0; dx < k; ++dx)
              sum += (*f.pixels)[std::size_t((y * k + dy) * f.stride_bytes + (x * k + dx) * c + ch)];
          EXPECT_EQ(img->pixels[std::size_t((y * img->width + x) * c + ch)], (sum + 8) / 16) << x << "," << y;
        }
  }
  EXPECT_TRUE(video::reduceForPreview(randomFrame(320, 10, cameras::PixelFormat::kRgb8, 1), 320)->width == 320);  // k = 1
  EXPECT_FALSE(video::reduceForPreview(randomFrame(64, 64, cameras::PixelFormat::kRgb8, 1), 0));
  cameras::CameraFrame empty;
  EXPECT_FALSE(video::reduceForPreview(empty, 32));
  cameras::CameraFrame short_buffer = randomFrame(64, 64, cameras::PixelFormat::kRgb8, 1);
  short_buffer.height = 100;  // claims more rows than it has
  EXPECT_FALSE(video::reduceForPreview(short_buffer, 32));
}

TEST(PreviewReduction, ABayerMosaicBecomesRgbInWholeCells) {
  // Cameras send their raw mosaic (#34): each preview pixel is the mean of each colour's samples
  // in its block, the block size rounded up to even so every block holds whole 2 x 2 cells.
  for (cameras::PixelFormat layout : {cameras::PixelFormat::kBayerRG8, cameras::PixelFormat::kBayerGR8,
                                      cameras::PixelFormat::kBayerGB8, cameras::PixelFormat::kBayerBG8}) {
    const cameras::CameraFrame f = randomFrame(1003, 517, layout, 5);
    const auto img = video::reduceForPreview(f, 400);  // ceil(1003 / 400) = 3, rounded up to 4
    ASSERT_TRUE(img) << cameras::pixelFormatName(layout);
    const int k = 4;
    EXPECT_EQ(img->width, 1003 / k);
    EXPECT_EQ(img->height, 517 / k);
    EXPECT_EQ(img->channels, 3);
    for (int y = 0; y < img->height; y += 5)
      for (int x = 0; x < img->width; x += 9) {
        unsigned sum[3] = {0, 0, 0}, count[3] = {0, 0, 0};
        for (int dy = 0; dy < k; ++dy)
          for (int dx = 0; dx < k; ++dx) {
            const int c = cameras::bayerChannelAt(layout, x * k + dx, y * k + dy);
            sum[c] += (*f.pixels)[std::size_t((y * k + dy) * f.stride_bytes + x * k + dx)];
            ++count[c];
          }
        for (int c = 0; c < 3; ++c)
          EXPECT_EQ(img->pixels[std::size_t((y * img->width + x) * 3 + c)], (sum[c] + count[c] / 2) / count[c])
              << cameras::pixelFormatName(layout) << " " << x << "," << y << " channel " << c;
      }
    // A uniform colour seen through the filter comes back as that colour.
    cameras::CameraFrame uniform = f;
    auto samples = std::make_shared<std::vector<std::uint8_t>>(f.pixels->size());
    const std::uint8_t colour[3] = {200, 100, 50};
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x)
        (*samples)[std::size_t(y * f.stride_bytes + x)] = colour[cameras::bayerChannelAt(layout, x, y)];
    uniform.pixels = samples;
    const auto flat = video::reduceForPreview(uniform, 100);
    ASSERT_TRUE(flat);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(flat->pixels[std::size_t(c)], colour[c]) << cameras::pixelFormatName(layout);
  }
}

using telesphere::test::smoothFrame;

/// Replay cameras → pairs → video streamer (+ preview, telemetry) → link server, in real time.
struct VideoRig {
  clock::SteadyClock clock;
  link::LinkEndpoints endpoints;
  link::LinkServer server;
  cameras::ReplayCamera left, right;
  stereo::StereoPairSource pairs;
  telemetry::TelemetryBatcher telemetry;
  video::PreviewStreamer preview;
  std::unique_ptr<link::media::MediaSender> media;  ///< the media path, when asked for
  video::VideoStreamer video;
  clock::SimClock arm_clock{1};
  arm::SimulatedArm arm{arm_clock};
  head::HeadController controller;
  head::JointStateBuffer buffer{controller.config().geometry};
  head::HeadLoop loop{arm, controller, buffer, server, arm_clock};
  services::RobotControl control{loop, &video};

  static link::LinkEndpoints at(int port) {
    link::LinkEndpoints e;
    e.base_port = port;
    return e;
  }
  static cameras::ReplayCameraConfig camera(const char* name) {
    cameras::ReplayCameraConfig c;
    c.name = name;
    c.fps = 30;
    return c;
  }
  static std::unique_ptr<link::media::MediaSender> mediaAt(int port, bool wanted) {
    if (!wanted) return nullptr;
    link::media::MediaSenderOptions options;
    options.bind_address = "127.0.0.1";
    options.port = static_cast<std::uint16_t>(port + link::LinkEndpoints::kMedia);
    std::string error;
    auto sender = link::media::MediaSender::start(options, &error);
    EXPECT_TRUE(sender) << error;
    return sender;
  }
  static video::VideoStreamerConfig videoConfig(telemetry::TelemetryBatcher* telemetry, video::PreviewStreamer* preview,
                                                link::media::MediaSender* media) {
    video::VideoStreamerConfig c;
    c.telemetry = telemetry;
    c.media = media;
    c.adaptive.nominal_fps = 30;
    c.on_sent = [preview](const stereo::StereoFrame& pair, std::uint64_t sequence) { preview->offer(pair, sequence); };
    return c;
  }
  explicit VideoRig(int port, bool with_media = false)
      : endpoints(at(port)),
        server(endpoints),
        left(clock, {smoothFrame(640, 360, 0.0)}, camera("left")),
        right(clock, {smoothFrame(640, 360, 1.0)}, camera("right")),
        pairs(left, right, stereo::StereoPairerOptions{.tolerance_ns = 5'000'000}),
        preview(server, video::PreviewOptions{.max_width = 160, .rate_hz = 20, .quality = 90}),
        media(mediaAt(port, with_media)),
        video(pairs, server, clock, nullptr, videoConfig(&telemetry, &preview, media.get())) {
    server.setControlHandler([this](const link::proto::ControlRequest& r) { return control.handle(r); });
    std::string error;
    left.start(&error);
    right.start(&error);
    preview.start();
    pairs.start();
    video.start();
  }
  ~VideoRig() {
    server.setControlHandler(nullptr);
    video.stop();
    preview.stop();
    pairs.stop();
    left.stop();
    right.stop();
  }
};

TEST(RobotConsoleServices, PreviewFramesArriveSmallAndDecodeToTheReducedImage) {
  VideoRig rig(27230);
  link::LinkClient client(rig.endpoints, {.frames = false, .previews = true});
  std::optional<link::ReceivedPreview> p;
  ASSERT_TRUE(eventually([&] { return (p = client.takeLatestPreview()).has_value(); }));
  EXPECT_EQ(p->preview.width(), 160u);
  EXPECT_EQ(p->preview.height(), 90u);
  EXPECT_EQ(p->preview.source_width(), 640u);
  EXPECT_GT(p->preview.sequence(), 0u);
  EXPECT_LT(p->left_jpeg.size(), 40000u);
  // Decode and compare with the reduction of the camera's frame (JPEG q90 4:2:0).
  tjhandle tj = tjInitDecompress();
  std::vector<std::uint8_t> rgb(160 * 90 * 3);
  ASSERT_EQ(tjDecompress2(tj, p->left_jpeg.data(), static_cast<unsigned long>(p->left_jpeg.size()), rgb.data(), 160, 0,
                          90, TJPF_RGB, 0),
            0);
  tjDestroy(tj);
  const auto want = video::reduceForPreview(smoothFrame(640, 360, 0.0), 160);
  double error = 0;
  for (std::size_t i = 0; i < rgb.size(); ++i) error += std::abs(int(rgb[i]) - int(want->pixels[i]));
  EXPECT_LT(error / double(rgb.size()), 2.5);  // mean absolute error, 8-bit levels
  // At most 20 previews a second whatever the camera rate.
  const auto before = rig.preview.published();
  std::this_thread::sleep_for(1s);
  EXPECT_LE(rig.preview.published() - before, 21u);
  EXPECT_GE(rig.preview.published() - before, 5u);
}

TEST(RobotConsoleServices, SentFramesBecomeTelemetryWithTheirStamps) {
  VideoRig rig(27240);
  ASSERT_TRUE(eventually([&] { return rig.video.stats().frames_sent >= 5; }));
  const auto batch = rig.telemetry.takeBatch();
  ASSERT_TRUE(batch);
  EXPECT_EQ(batch->batch(), 1u);
  ASSERT_GE(batch->frames_size(), 5);
  for (const auto& f : batch->frames()) {
    EXPECT_GT(f.capture_ns(), 0);
    EXPECT_GE(f.encoded_ns(), f.capture_ns());
    EXPECT_GE(f.sent_ns(), f.encoded_ns());
    EXPECT_GT(f.jpeg_bytes(), 1000u);
  }
  EXPECT_GT(batch->frames(1).sequence(), batch->frames(0).sequence());
  ASSERT_TRUE(eventually([&] { return rig.video.stats().frames_sent >= 7; }));
  EXPECT_EQ(rig.telemetry.takeBatch()->batch(), 2u);
}

/// Bytes on the wire of a frame whose encode started after this call: the one in flight now is
/// sent (telemetry first, then the count) and skipped, and so is anything sent before.
std::uint32_t bytesOfAFrameEncodedFromNow(VideoRig& rig) {
  const auto in_flight = rig.video.stats().frames_sent + 1;
  EXPECT_TRUE(eventually([&] { return rig.video.stats().frames_sent >= in_flight; }));
  rig.telemetry.takeBatch();
  const auto after = rig.video.stats().frames_sent + 1;
  EXPECT_TRUE(eventually([&] { return rig.video.stats().frames_sent >= after; }));
  const auto batch = rig.telemetry.takeBatch();
  EXPECT_TRUE(batch && batch->frames_size() > 0);
  return batch && batch->frames_size() > 0 ? batch->frames(batch->frames_size() - 1).jpeg_bytes() : 0;
}

TEST(RobotConsoleServices, JpegQualityThroughAControlRequestAndSettingsInEveryReply) {
  VideoRig rig(27250);
  link::LinkClient client(rig.endpoints, {.frames = false});
  link::proto::ControlRequest r;
  r.set_set_jpeg_quality(40);
  auto reply = client.request(r, 3000ms);
  ASSERT_TRUE(reply);
  EXPECT_TRUE(reply->ok()) << reply->error();
  EXPECT_EQ(reply->settings().jpeg_quality(), 40);
  EXPECT_EQ(rig.video.jpegSettings().quality, 40);
  EXPECT_EQ(reply->settings().jpeg_subsampling(), link::proto::CHROMA_420);
  EXPECT_EQ(reply->settings().visual_mode(), link::proto::VISUAL_MODE_FULL6D);
  EXPECT_DOUBLE_EQ(reply->settings().sphere_radius(), 1.0);
  for (int bad : {0, 101, -5}) {
    r.set_set_jpeg_quality(bad);
    reply = client.request(r, 3000ms);
    ASSERT_TRUE(reply);
    EXPECT_FALSE(reply->ok()) << bad;
    EXPECT_NE(reply->error().find("outside [1, 100]"), std::string::npos) << reply->error();
    EXPECT_EQ(reply->settings().jpeg_quality(), 40);  // what is in force, not what was asked
  }
  // Lower quality: smaller frames on the wire. The frame being encoded when the quality changes
  // still has the old one: the size is read from a frame whose encode began after the change.
  const std::uint32_t small = bytesOfAFrameEncodedFromNow(rig);
  r.set_set_jpeg_quality(95);
  ASSERT_TRUE(client.request(r, 3000ms)->ok());
  const std::uint32_t large = bytesOfAFrameEncodedFromNow(rig);
  EXPECT_GT(large, small * 3 / 2) << "q40 " << small << " B, q95 " << large << " B";

  link::proto::ControlRequest get;
  get.set_get_settings(true);
  reply = client.request(get, 3000ms);
  ASSERT_TRUE(reply && reply->ok());
  EXPECT_EQ(reply->settings().jpeg_quality(), 95);
  EXPECT_DOUBLE_EQ(reply->settings().filter_cutoff_hz(), 100.0);
  EXPECT_FALSE(reply->settings().media_path());

  // No media path on this robot: a cap is refused and said why.
  link::proto::ControlRequest cap;
  cap.set_set_media_cap_mbit(5);
  reply = client.request(cap, 3000ms);
  ASSERT_TRUE(reply);
  EXPECT_FALSE(reply->ok());
  EXPECT_NE(reply->error().find("no media path"), std::string::npos) << reply->error();
}

TEST(RobotConsoleServices, TheMediaCapThroughAControlRequestAndTheLinkInHealthAndTelemetry) {
  VideoRig rig(27350, true);
  link::LinkClient client(rig.endpoints, {.frames = false});
  link::proto::ControlRequest r;
  r.set_set_media_cap_mbit(3.0);
  auto reply = client.request(r, 3000ms);
  ASSERT_TRUE(reply);
  EXPECT_TRUE(reply->ok()) << reply->error();
  EXPECT_TRUE(reply->settings().media_path());
  EXPECT_DOUBLE_EQ(reply->settings().media_cap_mbit(), 3.0);
  EXPECT_DOUBLE_EQ(rig.media->capBps(), 3e6);
  for (double bad : {-1.0, 0.2, std::nan(""), std::numeric_limits<double>::infinity()}) {
    r.set_set_media_cap_mbit(bad);
    reply = client.request(r, 3000ms);
    ASSERT_TRUE(reply);
    EXPECT_FALSE(reply->ok()) << bad;
    EXPECT_FALSE(reply->error().empty());
    EXPECT_DOUBLE_EQ(reply->settings().media_cap_mbit(), 3.0) << "what is in force, not what was asked";
  }

  services::RobotHealthSources sources;
  sources.video = &rig.video;
  sources.loop = &rig.loop;
  sources.control = &rig.control;
  services::RobotHealthReporter reporter(sources, rig.clock);
  auto h = reporter.make();
  ASSERT_TRUE(h.has_media());
  EXPECT_EQ(h.media().port(), 27354u);
  EXPECT_TRUE(h.media().receiver_address().empty()) << "nobody has said hello";
  EXPECT_FALSE(h.media().now().receiver());
  EXPECT_DOUBLE_EQ(h.media().now().cap_mbit(), 3.0);

  // A receiver: the robot names it, measures the round trip, and every frame's telemetry carries the link.
  link::media::MediaReceiverOptions options;
  options.sender_port = 27354;
  std::string error;
  auto receiver = link::media::MediaReceiver::start(options, &error);
  ASSERT_TRUE(receiver) << error;
  ASSERT_TRUE(eventually([&] {
    while (receiver->waitNewest(0ms)) {
    }
    h = reporter.make();
    return h.media().now().receiver() && h.media().now().rtt_ms() >= 0 && h.media().frames_sent() >= 10;
  }, 5000ms));
  EXPECT_EQ(h.media().receiver_address().rfind("127.0.0.1:", 0), 0u) << h.media().receiver_address();
  EXPECT_LT(h.media().now().rtt_ms(), 100.0) << "loopback";
  EXPECT_GT(h.media().now().target_mbit(), 0.0);
  EXPECT_LE(h.media().now().target_mbit(), 3.0 + 1e-9);
  EXPECT_GT(h.media().datagrams_sent(), 10u);
  EXPECT_GT(h.media().rate_decisions_size(), 0);
  EXPECT_GT(h.media().stream_decisions_size(), 0) << "the stream adapts once a receiver listens";
  rig.telemetry.takeBatch();
  const auto from = rig.video.stats().frames_sent + 2;
  ASSERT_TRUE(eventually([&] { return rig.video.stats().frames_sent >= from; }));
  const auto batch = rig.telemetry.takeBatch();
  ASSERT_TRUE(batch && batch->frames_size() > 0);
  const auto& m = batch->frames(batch->frames_size() - 1).media();
  EXPECT_TRUE(m.receiver());
  EXPECT_DOUBLE_EQ(m.cap_mbit(), 3.0);
  EXPECT_GT(m.fps(), 0.0);
  EXPECT_GT(m.scale(), 0.0);
  EXPECT_GT(m.quality(), 0u);
  EXPECT_FALSE(m.limited_by().empty());

  // 0 lifts the cap.
  r.set_set_media_cap_mbit(0);
  reply = client.request(r, 3000ms);
  ASSERT_TRUE(reply && reply->ok());
  EXPECT_DOUBLE_EQ(reply->settings().media_cap_mbit(), 0.0);
  EXPECT_DOUBLE_EQ(reporter.make().media().now().cap_mbit(), 0.0);
}

TEST(RobotConsoleServices, HealthReportsCamerasVideoAndSettings) {
  VideoRig rig(27260);
  services::RobotHealthSources sources;
  sources.cameras = {&rig.left, &rig.right};
  sources.pairs = &rig.pairs;
  sources.video = &rig.video;
  sources.loop = &rig.loop;
  sources.control = &rig.control;
  sources.server = &rig.server;
  sources.telemetry = &rig.telemetry;
  sources.arm = "simulated xArm 6";
  sources.cameras_kind = "replay";
  services::RobotHealthReporter reporter(sources, rig.clock);
  std::this_thread::sleep_for(1s);
  const auto h = reporter.make();
  EXPECT_EQ(h.instance(), rig.server.instance());
  ASSERT_EQ(h.cameras_size(), 2);
  EXPECT_EQ(h.cameras(0).name(), "left");
  EXPECT_NEAR(h.cameras(0).fps(), 30.0, 6.0);
  EXPECT_EQ(h.cameras(0).width(), 640u);
  EXPECT_EQ(h.cameras(0).exposure_us(), 5000u);
  EXPECT_GT(h.frames_sent(), 15u);
  EXPECT_EQ(h.settings().jpeg_quality(), 90);
  EXPECT_EQ(h.arm(), "simulated xArm 6");
  EXPECT_TRUE(h.arm_ok());
  EXPECT_EQ(h.head_target_age_ns(), -1);  // no head pose yet
  EXPECT_GT(h.t_ns(), h.started_ns());
}

}  // namespace
}  // namespace telesphere::robot
