// SPDX-License-Identifier: MIT
/// @brief DecodePool: every job decoded exactly as a lone JpegDecoder decodes it, bad JPEGs
///        answered with their reason, plane buffers recycled (bounded, never reused while held,
///        valid after the pool is gone); SourceImage::yuv takes the planes without a copy.
#include <gtest/gtest.h>

#include "tests/xr/jpeg_test_images.h"
#include "xr/video/decode_pool.h"
#include "xr/render/source_image.h"

namespace telesphere::xr {
namespace {

using test::referenceDecode;

void expectSamePlanes(const render::YuvPlanes& a, const render::YuvPlanes& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.chroma_width, b.chroma_width);
  EXPECT_EQ(a.chroma_height, b.chroma_height);
  EXPECT_EQ(a.subsampling, b.subsampling);
  EXPECT_TRUE(a.y == b.y);
  EXPECT_TRUE(a.u == b.u);
  EXPECT_TRUE(a.v == b.v);
}

video::DecodeJob jobFor(const std::vector<std::uint8_t>& jpeg, int w = 0, int h = 0) {
  video::DecodeJob job;
  job.jpeg = jpeg;
  job.expected_width = w;
  job.expected_height = h;
  return job;
}

TEST(DecodePool, DefaultsToOneThreadPerCore) {
  video::DecodePool pool;
  EXPECT_EQ(pool.threads(), static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  video::DecodePool three(3);
  EXPECT_EQ(three.threads(), 3);
}

TEST(DecodePool, ManyJobsInParallelMatchAReferenceDecode) {
  std::vector<std::vector<std::uint8_t>> jpegs;
  const int subsamps[] = {TJSAMP_420, TJSAMP_444, TJSAMP_422, TJSAMP_GRAY};
  for (std::uint32_t i = 0; i < 12; ++i)
    jpegs.push_back(test::texturedJpeg(96 + 8 * static_cast<int>(i), 64, i, subsamps[i % 4]));
  video::DecodePool pool(3);
  std::vector<std::future<video::DecodeResult>> futures;
  for (const auto& jpeg : jpegs) futures.push_back(pool.submit(jobFor(jpeg)));
  for (std::size_t i = 0; i < jpegs.size(); ++i) {
    const video::DecodeResult r = futures[i].get();
    ASSERT_EQ(r.error, video::JpegDecodeError::kNone) << r.message;
    ASSERT_TRUE(r.planes);
    EXPECT_GT(r.decode_ms, 0.0);  // a decode takes time (0: not measured)
    expectSamePlanes(*r.planes, referenceDecode(jpegs[i]));
  }
}

TEST(DecodePool, BadJpegsComeBackWithTheirReason) {
  video::DecodePool pool(2);
  const auto good = test::texturedJpeg(64, 48, 1);
  const std::vector<std::uint8_t> truncated(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(good.size() / 2));
  const auto huge = test::withHeaderSize(good, 60000, 60000);
  const auto unsupported = test::texturedJpeg(64, 48, 2, TJSAMP_411);
  const std::vector<std::uint8_t> empty;
  const struct {
    video::DecodeJob job;
    video::JpegDecodeError expected;
  } cases[] = {{jobFor(truncated), video::JpegDecodeError::kCorrupt},
               {jobFor(empty), video::JpegDecodeError::kCorrupt},
               {jobFor(huge), video::JpegDecodeError::kTooLarge},
               {jobFor(good, 640, 480), video::JpegDecodeError::kSizeMismatch},
               {jobFor(unsupported), video::JpegDecodeError::kUnsupported}};
  for (const auto& c : cases) {
    const video::DecodeResult r = pool.submit(c.job).get();
    EXPECT_EQ(r.error, c.expected) << video::jpegDecodeErrorName(c.expected) << ": " << r.message;
    EXPECT_FALSE(r.planes);
    EXPECT_FALSE(r.message.empty());
  }
  const video::DecodeResult r = pool.submit(jobFor(good, 64, 48)).get();
  EXPECT_EQ(r.error, video::JpegDecodeError::kNone) << r.message;
  // 60000² planes were never allocated: no plane set grew beyond the good image.
  EXPECT_LE(r.planes->y.capacity(), std::size_t{64} * 48);
}

TEST(DecodePool, PlaneBuffersAreRecycledButNeverWhileHeld) {
  video::DecodePool pool(2);
  const auto a = test::texturedJpeg(128, 96, 3);
  const auto b = test::texturedJpeg(128, 96, 4);
  for (int i = 0; i < 20; ++i) {
    const video::DecodeResult r = pool.submit(jobFor(i % 2 ? a : b)).get();
    ASSERT_EQ(r.error, video::JpegDecodeError::kNone);
  }  // each result released before the next job: one plane set serves them all
  EXPECT_EQ(pool.planesAllocated(), 1u);

  const video::DecodeResult held = pool.submit(jobFor(a)).get();
  const std::uint8_t* held_y = held.planes->y.data();
  for (int i = 0; i < 10; ++i) {
    const video::DecodeResult r = pool.submit(jobFor(b)).get();
    ASSERT_EQ(r.error, video::JpegDecodeError::kNone);
    EXPECT_NE(r.planes->y.data(), held_y);
  }
  expectSamePlanes(*held.planes, referenceDecode(a));  // untouched by the later decodes
  EXPECT_EQ(pool.planesAllocated(), 2u);
}

TEST(DecodePool, ResultsOutliveThePool) {
  const auto jpeg = test::texturedJpeg(80, 60, 5);
  std::shared_ptr<const render::YuvPlanes> planes;
  {
    video::DecodePool pool(1);
    planes = pool.submit(jobFor(jpeg)).get().planes;
  }
  ASSERT_TRUE(planes);
  expectSamePlanes(*planes, referenceDecode(jpeg));
  planes.reset();  // the pool's recycler is gone: freed, not recycled (ASan checks)
}

TEST(DecodePool, JobsQueuedAtDestructionStillFinish) {
  const auto jpeg = test::texturedJpeg(160, 120, 6);
  std::vector<std::future<video::DecodeResult>> futures;
  {
    video::DecodePool pool(1);
    for (int i = 0; i < 8; ++i) futures.push_back(pool.submit(jobFor(jpeg)));
  }
  for (auto& f : futures) EXPECT_EQ(f.get().error, video::JpegDecodeError::kNone);
}

TEST(SourceImageYuv, TakesTheDecodersPlanesWithoutACopy) {
  const auto jpeg = test::texturedJpeg(66, 50, 7);
  video::DecodePool pool(1);
  const video::DecodeResult r = pool.submit(jobFor(jpeg)).get();
  ASSERT_TRUE(r.planes);
  const render::SourceImage image = render::SourceImage::yuv(r.planes);
  EXPECT_EQ(image.planes.get(), r.planes.get());
  EXPECT_EQ(image.planes->y.data(), r.planes->y.data());
  EXPECT_TRUE(image.bytes.empty());
  EXPECT_EQ(image.width, 66);
  EXPECT_EQ(image.height, 50);
  EXPECT_EQ(image.chroma_width, 33);
  EXPECT_EQ(image.chroma_height, 25);
  EXPECT_TRUE(image.consistent());
  // sample() reads the shared planes. At luma texel (10, 20) the chroma planes (33×25) are
  // sampled at (4.75, 9.75): texels 4..5 × 9..10 with weights 0.75 toward the second.
  const auto& p = *r.planes;
  const auto chroma = [&](const std::vector<std::uint8_t>& c) {
    const auto at = [&](int x, int y) { return c[static_cast<std::size_t>(y) * 33 + x] / 255.0; };
    const double top = 0.25 * at(4, 9) + 0.75 * at(5, 9);
    const double bottom = 0.25 * at(4, 10) + 0.75 * at(5, 10);
    return 0.25 * top + 0.75 * bottom - 128.0 / 255.0;
  };
  const double Y = p.y[20 * 66 + 10] / 255.0, cb = chroma(p.u), cr = chroma(p.v);
  const Eigen::Vector4d s = image.sample(Eigen::Vector2d(10, 20));
  EXPECT_NEAR(s.x(), std::clamp(Y + 1.402 * cr, 0.0, 1.0), 1e-9);
  EXPECT_NEAR(s.y(), std::clamp(Y - 0.344136 * cb - 0.714136 * cr, 0.0, 1.0), 1e-9);
  EXPECT_NEAR(s.z(), std::clamp(Y + 1.772 * cb, 0.0, 1.0), 1e-9);
  // Planes of the wrong size, or none, are not consistent.
  EXPECT_FALSE(render::SourceImage::yuv(nullptr).consistent());
  auto bad = std::make_shared<render::YuvPlanes>(p);
  bad->v.pop_back();
  EXPECT_FALSE(render::SourceImage::yuv(std::shared_ptr<const render::YuvPlanes>(bad)).consistent());
  auto gray = std::make_shared<render::YuvPlanes>(p);
  gray->u.clear();
  gray->v.clear();
  gray->chroma_width = gray->chroma_height = 0;
  // Greyscale (a Mono8 camera's JPEG): Y only, no chroma, grey out: R = G = B = Y.
  const render::SourceImage grey_image = render::SourceImage::yuv(std::shared_ptr<const render::YuvPlanes>(gray));
  ASSERT_TRUE(grey_image.consistent());
  const Eigen::Vector4d g = grey_image.sample(Eigen::Vector2d(10, 20));
  EXPECT_NEAR(g.x(), Y, 1e-12);
  EXPECT_NEAR(g.y(), Y, 1e-12);
  EXPECT_NEAR(g.z(), Y, 1e-12);
  gray->y.pop_back();
  EXPECT_FALSE(render::SourceImage::yuv(std::shared_ptr<const render::YuvPlanes>(gray)).consistent());
}

}  // namespace
}  // namespace telesphere::xr
