// SPDX-License-Identifier: MIT
/// @brief StereoFrameDecoder on a real LinkServer + LinkClient over loopback: decoded planes equal
///        a reference decode and reach SourceImage without a copy; corrupt, truncated, oversized,
///        mismatched and unsupported frames are dropped with their counted reason and the next good
///        frame still arrives; a slow consumer sees only ever-newer frames, superseded frames are
///        counted and plane memory stays bounded; per-stage latency figures are filled.
#include <gtest/gtest.h>

#include <deque>
#include <mutex>
#include <thread>

#include "tests/eventually.h"
#include "robot/link/link_client.h"
#include "robot/link/link_server.h"
#include "tests/xr/jpeg_test_images.h"
#include "xr/render/source_image.h"
#include "xr/video/stereo_frame_decoder.h"

namespace telesphere::xr {
namespace {

using namespace std::chrono_literals;

link::LinkEndpoints stereoEndpoints(int n) {
  link::LinkEndpoints e;
  e.base_port = 27340 + 8 * n;  // four ports each, clear of test_head_loop's 27200-27330 and 27380
  return e;
}

using ::telesphere::test::eventually;

using Bytes = std::shared_ptr<const std::vector<std::uint8_t>>;

Bytes share(std::vector<std::uint8_t> v) { return std::make_shared<const std::vector<std::uint8_t>>(std::move(v)); }

link::proto::StereoFrame message(std::uint64_t sequence, int w, int h) {
  link::proto::StereoFrame f;
  f.set_sequence(sequence);
  const std::int64_t now = link::linkNowNs();
  for (auto* image : {f.mutable_left(), f.mutable_right()}) {
    image->set_width(static_cast<std::uint32_t>(w));
    image->set_height(static_cast<std::uint32_t>(h));
    image->set_capture_ns(now - 7'000'000);
  }
  f.mutable_stamps()->set_capture_ns(now - 7'000'000);  // 7 ms before now
  f.mutable_stamps()->set_encoded_ns(now - 2'000'000);  // encoding took 5 ms
  return f;
}

using test::referenceDecode;

bool samePlanes(const render::YuvPlanes& a, const render::YuvPlanes& b) {
  return a.width == b.width && a.height == b.height && a.y == b.y && a.u == b.u && a.v == b.v;
}

struct Rig {
  explicit Rig(int n, video::StereoFrameDecoder::Options options = {})
      : server(stereoEndpoints(n)), client(stereoEndpoints(n)), decoder(client, options) {}

  /// Publishes good frames (sequence 1, 2, …) until one is decoded (a PUB drops what it sends
  /// before the SUB has joined), then one more and waits for exactly that one: frames arrive in
  /// order, so once it is out, no earlier frame is still on its way. Returns it.
  std::shared_ptr<const video::DecodedStereoFrame> connect() {
    for (int i = 0; i < 500; ++i) {
      server.publishStereoFrame(message(++sequence, 64, 48), left, right);
      if (decoder.waitNewer(0, 20ms)) return good();
    }
    return nullptr;
  }

  /// Publishes a good frame and waits for it to come out decoded (sent again, same sequence,
  /// if the PUB socket lost it: what is tested here is the decoder, not ZeroMQ's delivery).
  std::shared_ptr<const video::DecodedStereoFrame> good() {
    const std::uint64_t s = ++sequence;
    std::shared_ptr<const video::DecodedStereoFrame> f;
    publishUntil(message(s, 64, 48), left, right, [&] { return (f = decoder.waitNewer(s - 1, 0ms)) != nullptr; });
    return f;
  }

  /// Publishes a frame every 500 ms, up to 20 times, until `done`; whether it came.
  template <typename Done>
  bool publishUntil(const link::proto::StereoFrame& m, const Bytes& l, const Bytes& r, Done done) {
    for (int attempt = 0; attempt < 20; ++attempt) {
      server.publishStereoFrame(m, l, r);
      if (eventually(done, 500ms)) return true;
    }
    return false;
  }

  link::LinkServer server;
  link::LinkClient client;
  video::StereoFrameDecoder decoder;
  std::uint64_t sequence = 0;
  std::vector<std::uint8_t> left_jpeg = test::texturedJpeg(64, 48, 11);
  std::vector<std::uint8_t> right_jpeg = test::texturedJpeg(64, 48, 12, TJSAMP_444);
  Bytes left = share(left_jpeg), right = share(right_jpeg);
};

TEST(StereoFrameDecoder, DecodesBothImagesAsAReferenceDecoderDoes) {
  video::StereoFrameDecoder::Options options;
  options.threads = 2;
  Rig rig(0, options);
  ASSERT_TRUE(rig.connect());
  const auto f = rig.good();
  ASSERT_TRUE(f);
  EXPECT_EQ(f->frame.sequence(), rig.sequence);
  ASSERT_TRUE(f->left && f->right);
  EXPECT_TRUE(samePlanes(*f->left, referenceDecode(rig.left_jpeg)));
  EXPECT_TRUE(samePlanes(*f->right, referenceDecode(rig.right_jpeg)));
  EXPECT_EQ(f->right->subsampling, link::ChromaSubsampling::k444);
  const auto& st = f->frame.stamps();
  EXPECT_GE(st.received_ns(), st.sent_ns());  // one clock on loopback
  EXPECT_GE(st.decoded_ns(), st.received_ns());
  // The renderer's hand-over: the same planes, not a copy.
  const render::SourceImage image = render::SourceImage::yuv(f->left);
  EXPECT_EQ(image.planes.get(), f->left.get());
  EXPECT_EQ(image.planes->y.data(), f->left->y.data());
  EXPECT_TRUE(image.consistent());
  EXPECT_EQ(rig.decoder.newest(), f);
  EXPECT_FALSE(rig.decoder.waitNewer(rig.sequence, 30ms));  // nothing newer was sent
}

TEST(StereoFrameDecoder, BadFramesAreDroppedWithTheirReasonAndTheStreamResumes) {
  Rig rig(1);
  ASSERT_TRUE(rig.connect());
  const auto good = rig.left_jpeg;
  struct Case {
    const char* name;
    std::vector<std::uint8_t> jpeg;
    int message_w, message_h;
    video::FrameDropReason reason;
  };
  std::vector<std::uint8_t> corrupt = good;
  for (std::size_t i = corrupt.size() / 3; i < corrupt.size() - 2; ++i)
    corrupt[i] = static_cast<std::uint8_t>(i * 37);  // entropy data and EOI overwritten
  const std::vector<Case> cases = {
      {"truncated", std::vector<std::uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(good.size() / 2)), 64, 48, video::FrameDropReason::kCorrupt},
      {"garbage", std::vector<std::uint8_t>(900, 0x5a), 64, 48, video::FrameDropReason::kCorrupt},
      {"corrupt", corrupt, 64, 48, video::FrameDropReason::kCorrupt},
      {"60000x60000 header", test::withHeaderSize(good, 60000, 60000), 64, 48, video::FrameDropReason::kTooLarge},
      {"message says 80x48", good, 80, 48, video::FrameDropReason::kSizeMismatch},
      {"4:1:1", test::texturedJpeg(64, 48, 13, TJSAMP_411), 64, 48, video::FrameDropReason::kUnsupported},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto before = rig.decoder.stats();
    const std::uint64_t bad_sequence = ++rig.sequence;
    // The bad image on the right, a good one on the left: the whole pair goes. Sent again, same
    // sequence, while it is not counted: the frames PUB (high-water mark 6) drops what a loaded
    // machine's subscriber has not taken yet, like good() allows for; a copy that does arrive after
    // the first is not decoded either.
    const Bytes bad = share(c.jpeg);
    ASSERT_TRUE(rig.publishUntil(message(bad_sequence, c.message_w, c.message_h), rig.left, bad, [&] {
      return rig.decoder.stats().dropped(c.reason) > before.dropped(c.reason);
    }));
    const auto after = rig.decoder.stats();
    EXPECT_EQ(after.decoded, before.decoded);
    ASSERT_TRUE(rig.decoder.newest());
    EXPECT_LT(rig.decoder.newest()->frame.sequence(), bad_sequence);  // never published
    const auto next = rig.good();
    ASSERT_TRUE(next);
    EXPECT_EQ(next->frame.sequence(), rig.sequence);
    EXPECT_TRUE(samePlanes(*next->right, referenceDecode(rig.right_jpeg)));
  }
  // A message claiming 100000×100000 never gets past the link (nothing allocated for it).
  const auto link_before = rig.client.stats().dropped(link::DropReason::kBadImageSize);
  rig.server.publishStereoFrame(message(++rig.sequence, 100000, 100000), rig.left, rig.right);
  ASSERT_TRUE(eventually([&] { return rig.client.stats().dropped(link::DropReason::kBadImageSize) > link_before; }));
  ASSERT_TRUE(rig.good());
  EXPECT_LE(rig.decoder.pool().planesAllocated(), 8u);  // bad frames allocated nothing extra
}

/// Threads in the pool: 1 decodes left and right one after the other, one pair at a time; 4 has
/// two pairs in flight, which must still come out in arrival order.
class StereoFrameDecoderThreads : public ::testing::TestWithParam<int> {};

TEST_P(StereoFrameDecoderThreads, ASlowConsumerSeesOnlyNewerFramesAndNothingQueues) {
  video::StereoFrameDecoder::Options options;
  options.threads = GetParam();
  Rig rig(GetParam() == 1 ? 2 : 4, options);
  ASSERT_TRUE(rig.connect());
  // Large enough that decoding takes far longer than publishing a burst.
  constexpr int kW = 1280, kH = 960;
  const auto big_left = test::texturedJpeg(kW, kH, 21);
  const auto big_right = test::texturedJpeg(kW, kH, 22);
  const Bytes l = share(big_left), r = share(big_right);
  const auto held = rig.decoder.newest();  // a consumer that keeps an old frame meanwhile
  const render::YuvPlanes held_copy = *held->left;
  constexpr int kBurst = 40;
  for (int i = 0; i < kBurst; ++i) rig.server.publishStereoFrame(message(++rig.sequence, kW, kH), l, r);
  const std::uint64_t last = rig.sequence;

  // The consumer reads now and then; what it sees only ever gets newer, ending at the last frame.
  // (The PUB socket drops what exceeds its high-water mark, so the last frame is sent again,
  // same sequence, whenever the consumer waited in vain.)
  std::uint64_t seen = held->frame.sequence();
  for (int round = 0; round < 200 && seen != last; ++round) {
    const auto f = rig.decoder.waitNewer(seen, 200ms);
    if (!f) {
      rig.server.publishStereoFrame(message(last, kW, kH), l, r);
      continue;
    }
    EXPECT_GT(f->frame.sequence(), seen);
    seen = f->frame.sequence();
    std::this_thread::sleep_for(5ms);  // a slow consumer
  }
  ASSERT_EQ(seen, last);
  EXPECT_TRUE(samePlanes(*rig.decoder.newest()->left, referenceDecode(big_left)));

  // A consumer that is away while pairs keep coming: nothing queues for it. Whether pairs are
  // superseded while one decodes depends on how fast this machine decodes (CI under load once
  // decoded every pair of the burst in time), so the burst here is made to replace an unread pair
  // whatever the speed: first a pair decoded and left unread, then the burst.
  const auto before = rig.decoder.stats();
  const std::uint64_t unread = ++rig.sequence;
  for (int attempt = 0; attempt < 20 && rig.decoder.stats().decoded == before.decoded; ++attempt) {
    rig.server.publishStereoFrame(message(unread, kW, kH), l, r);
    eventually([&] { return rig.decoder.stats().decoded > before.decoded; }, 500ms);
  }
  const auto after_unread = rig.decoder.stats();
  ASSERT_GT(after_unread.decoded, before.decoded);  // a pair published after the last read
  for (int i = 0; i < kBurst; ++i) rig.server.publishStereoFrame(message(++rig.sequence, kW, kH), l, r);
  const std::uint64_t last_away = rig.sequence;
  // Back: the first read is already of the burst, never the pair left unread; then only newer.
  seen = unread;
  for (int round = 0; round < 200 && seen != last_away; ++round) {
    const auto f = rig.decoder.waitNewer(seen, 200ms);
    if (!f) {
      rig.server.publishStereoFrame(message(last_away, kW, kH), l, r);
      continue;
    }
    EXPECT_GT(f->frame.sequence(), seen);
    seen = f->frame.sequence();
  }
  ASSERT_EQ(seen, last_away);
  const auto s = rig.decoder.stats();
  // The pair left unread was replaced, counted; every pair of the burst the decoder took was
  // published or superseded, counted: none of them is waiting anywhere.
  EXPECT_GE(s.replaced_unread, after_unread.replaced_unread + 1);
  EXPECT_GT(s.decoded, after_unread.decoded);
  // Plane sets stay bounded (slot + held + in flight + free), and the held frame is intact.
  // (4 threads: a second pair in flight, two more sets.)
  EXPECT_LE(rig.decoder.pool().planesAllocated(), GetParam() == 1 ? 10u : 12u);
  EXPECT_TRUE(samePlanes(*held->left, held_copy));
}

INSTANTIATE_TEST_SUITE_P(Pool, StereoFrameDecoderThreads, ::testing::Values(1, 4));

TEST(StereoFrameDecoder, StatsCoverEveryStage) {
  Rig rig(3);
  ASSERT_TRUE(rig.connect());
  ASSERT_TRUE(eventually([&] { return rig.client.clock().estimate().has_value(); }));
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(rig.good());
  const auto s = rig.decoder.stats();
  EXPECT_GE(s.decoded, 6u);
  EXPECT_GT(s.fps, 0.0);
  EXPECT_GE(s.decode.n, 10u);
  EXPECT_GT(s.decode.p50_ms, 0.0);
  EXPECT_GE(s.decode.p99_ms, s.decode.p50_ms);
  EXPECT_NEAR(s.capture_to_encoded.p50_ms, 5.0, 1e-9);  // as stamped by message()
  EXPECT_GE(s.encoded_to_sent.n, 6u);
  EXPECT_GE(s.encoded_to_sent.p50_ms, 2.0);  // encoded 2 ms before the message was made
  EXPECT_GE(s.sent_to_received.n, 5u);
  // One clock on loopback: the offset estimate is good to half a round trip.
  const double half_rtt_ms = 0.5e-6 * static_cast<double>(rig.client.clock().estimate()->round_trip_ns);
  EXPECT_GE(s.sent_to_received.p50_ms, -half_rtt_ms - 2.0);  // 2 ms: the estimate may have moved
  EXPECT_GE(s.received_to_decoded.n, 6u);
  EXPECT_GT(s.received_to_decoded.p50_ms, 0.0);  // one clock: decoding after receiving takes time
  EXPECT_GE(s.capture_to_decoded.n, 5u);
  EXPECT_GE(s.capture_to_decoded.p50_ms, 7.0 - half_rtt_ms - 2.0);
  for (int r = 0; r < static_cast<int>(video::FrameDropReason::kCount); ++r) {
    if (static_cast<video::FrameDropReason>(r) == video::FrameDropReason::kSuperseded) continue;
    EXPECT_EQ(s.dropped_by_reason[static_cast<std::size_t>(r)], 0u) << video::frameDropReasonName(static_cast<video::FrameDropReason>(r));
  }
}

}  // namespace
}  // namespace telesphere::xr

namespace telesphere::xr {
namespace {

TEST(StereoFrameDecoder, RowsTheMediaPathLostArePaintedFromThePreviousFrame) {
  // Frames from a frame source (as the media path hands them over), no ZeroMQ frame at all: the
  // first whole, the second with rows [16, 32) of the left image and [40, 48) of the right lost.
  const auto a_left = test::texturedJpeg(64, 48, 21), a_right = test::texturedJpeg(64, 48, 22);
  const auto b_left = test::texturedJpeg(64, 48, 23), b_right = test::texturedJpeg(64, 48, 24);
  std::mutex mutex;
  std::deque<link::ReceivedFrame> queue;
  const auto push = [&](std::uint64_t sequence, const std::vector<std::uint8_t>& l, const std::vector<std::uint8_t>& r,
                        std::vector<std::pair<int, int>> l_lost, std::vector<std::pair<int, int>> r_lost) {
    link::ReceivedFrame f;
    f.frame = message(sequence, 64, 48);
    f.frame.mutable_stamps()->set_received_ns(link::linkNowNs());
    f.left_jpeg = l;
    f.right_jpeg = r;
    f.left_lost_rows = std::move(l_lost);
    f.right_lost_rows = std::move(r_lost);
    std::lock_guard lock(mutex);
    queue.push_back(std::move(f));
  };
  video::StereoFrameDecoder::Options options;
  options.frame_source = [&](std::chrono::milliseconds timeout) -> std::optional<link::ReceivedFrame> {
    {
      std::lock_guard lock(mutex);
      if (!queue.empty()) {
        auto f = std::move(queue.front());
        queue.pop_front();
        return f;
      }
    }
    std::this_thread::sleep_for(std::min(timeout, std::chrono::milliseconds(5)));
    return std::nullopt;
  };
  link::LinkClient client(stereoEndpoints(7));  // nobody serves it: the frames come from the source
  video::StereoFrameDecoder decoder(client, options);
  push(1, a_left, a_right, {}, {});
  const auto first = decoder.waitNewer(0, 2000ms);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->rows_concealed, 0);
  push(2, b_left, b_right, {{16, 32}}, {{40, 60}});  // the right range runs past the image: clamped
  const auto second = decoder.waitNewer(1, 2000ms);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->rows_concealed, 16 + 8);
  EXPECT_EQ(second->rows_grey, 0);
  const render::YuvPlanes ra = referenceDecode(a_left), rb = referenceDecode(b_left);
  const auto row = [](const render::YuvPlanes& p, int y) {
    return std::vector<std::uint8_t>(p.y.begin() + y * p.width, p.y.begin() + (y + 1) * p.width);
  };
  const render::YuvPlanes& got = *second->left;
  for (int y = 0; y < 48; ++y) EXPECT_EQ(row(got, y), row(y >= 16 && y < 32 ? ra : rb, y)) << "row " << y;
  // 4:2:0: chroma rows 8..16 come from the first frame too.
  const auto chroma_row = [](const render::YuvPlanes& p, int y) {
    return std::vector<std::uint8_t>(p.u.begin() + y * p.chroma_width, p.u.begin() + (y + 1) * p.chroma_width);
  };
  for (int y = 0; y < 24; ++y) EXPECT_EQ(chroma_row(got, y), chroma_row(y >= 8 && y < 16 ? ra : rb, y)) << "chroma row " << y;
  const auto stats = decoder.stats();
  EXPECT_EQ(stats.frames_concealed, 1u);
  EXPECT_EQ(stats.rows_concealed, 24u);

  // A lost band in a frame of another size than the last: nothing to paint from, left grey.
  const auto small = test::texturedJpeg(32, 32, 25);
  push(3, small, small, {{0, 16}}, {});
  {  // the message must say the new size (the decoder checks it against the JPEG's)
    std::lock_guard lock(mutex);
    queue.back().frame = message(3, 32, 32);
  }
  const auto third = decoder.waitNewer(2, 2000ms);
  ASSERT_TRUE(third);
  EXPECT_EQ(third->rows_grey, 16);
  EXPECT_EQ(third->rows_concealed, 0);
}

}  // namespace
}  // namespace telesphere::xr
