// SPDX-License-Identifier: MIT
/// @brief The upload ring on a real GL context (EGL surfaceless, llvmpipe here): slots are given
///        out only for the size the ring is made for and never twice; a slot the GL copied from
///        comes back only after its fence and its last holder; textures copied from a slot hold
///        exactly the bytes the same planes give from the decoder's own memory (greyscale too);
///        a size change retires the old buffer once its slots are back; the decode pool decodes
///        into slots, falls back to its own memory when none is free, and gives a slot back on a
///        corrupt JPEG; planes still held when the ring goes stay readable.
#include <gtest/gtest.h>

#include <random>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "shaders/egl_context.h"
#include "tests/xr/jpeg_test_images.h"
#include "xr/video/decode_pool.h"
#include "xr/render/gpu_camera.h"
#include "xr/render/upload_ring.h"

namespace telesphere::xr {
namespace {

constexpr render::PlaneLayout k420{64, 36, 32, 18};

class UploadRingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    context_ = gl::EglContext::createSurfaceless(&error);
    ASSERT_TRUE(context_) << error;
    auto calibration = calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
    ASSERT_TRUE(calibration) << calibration.error().describe();
    const auto scaled = calib::atResolution(calibration->cameras[0], 64, 36, &error);
    ASSERT_TRUE(scaled) << error;
    camera_ = std::make_unique<calib::GenericCamera>(scaled->camera);
  }

  /// Planes of `layout` in a slot, filled with seeded noise.
  static std::shared_ptr<const render::YuvPlanes> fillSlot(std::shared_ptr<const render::UploadSlot> slot, std::uint32_t seed) {
    std::mt19937 rng(seed);
    const render::PlaneLayout& l = slot->layout;
    for (std::size_t i = 0; i < l.lumaBytes(); ++i) slot->y[i] = std::uint8_t(rng());
    for (std::size_t i = 0; i < l.chromaBytes(); ++i) {
      slot->u[i] = std::uint8_t(rng());
      slot->v[i] = std::uint8_t(rng());
    }
    auto planes = std::make_shared<render::YuvPlanes>();
    planes->width = l.width;
    planes->height = l.height;
    planes->chroma_width = l.chroma_width;
    planes->chroma_height = l.chroma_height;
    planes->subsampling = l.chromaBytes() == 0 ? link::ChromaSubsampling::kGray : link::ChromaSubsampling::k420;
    planes->slot = std::move(slot);
    return planes;
  }

  /// The same bytes in the planes' own memory.
  static std::shared_ptr<const render::YuvPlanes> ownCopy(const render::YuvPlanes& in) {
    auto out = std::make_shared<render::YuvPlanes>();
    out->width = in.width;
    out->height = in.height;
    out->chroma_width = in.chroma_width;
    out->chroma_height = in.chroma_height;
    out->subsampling = in.subsampling;
    const auto copy = [](std::span<const std::uint8_t> s) { return std::vector<std::uint8_t>(s.begin(), s.end()); };
    out->y = copy(in.yPlane());
    out->u = copy(in.uPlane());
    out->v = copy(in.vPlane());
    return out;
  }

  /// Texture unit `unit`'s bytes after GpuCamera::bindImage.
  static std::vector<std::uint8_t> texture(const render::GpuCamera& camera, int unit, std::size_t bytes) {
    camera.bindImage();
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    GLint id = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &id);
    glActiveTexture(GL_TEXTURE0);
    std::vector<std::uint8_t> out(bytes);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(GLuint(id), 0, GL_RED, GL_UNSIGNED_BYTE, GLsizei(bytes), out.data());
    return out;
  }

  std::unique_ptr<gl::EglContext> context_;
  std::unique_ptr<calib::GenericCamera> camera_;
};

TEST_F(UploadRingTest, SlotsAreGivenOutOnlyForTheSizeTheRingIsMadeForAndNeverTwice) {
  render::UploadRing ring(3);
  auto source = ring.source();
  ASSERT_TRUE(source);
  EXPECT_FALSE(source->take(k420)) << "no ring before prepare";
  std::string error;
  ASSERT_TRUE(ring.prepare(k420, &error)) << error;
  EXPECT_FALSE(source->take({64, 36, 64, 36})) << "another layout";
  std::vector<std::shared_ptr<const render::UploadSlot>> held;
  for (int i = 0; i < 3; ++i) {
    held.push_back(source->take(k420));
    ASSERT_TRUE(held.back());
  }
  EXPECT_NE(held[0]->index, held[1]->index);
  EXPECT_NE(held[1]->index, held[2]->index);
  EXPECT_NE(held[0]->index, held[2]->index);
  EXPECT_GE(held[1]->y_offset, held[0]->y_offset + k420.bytes()) << "slots do not overlap";
  EXPECT_FALSE(source->take(k420)) << "all held";
  const auto counts = source->counts();
  EXPECT_EQ(counts.taken, 3u);
  EXPECT_EQ(counts.none_free, 1u);
  EXPECT_EQ(counts.other_layout, 2u);
  EXPECT_EQ(ring.occupancy().held, 3);

  // Never copied from: free as soon as the last holder lets go.
  const int index = held[1]->index;
  auto copy = held[1];
  held[1].reset();
  EXPECT_FALSE(source->take(k420)) << "still held by the copy";
  copy.reset();
  const auto again = source->take(k420);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->index, index);
  EXPECT_FALSE(render::UploadRing(0).source()) << "0 slots: the ring is off";
}

TEST_F(UploadRingTest, ACopiedSlotComesBackOnlyAfterItsLastHolderAndItsFence) {
  render::UploadRing ring(1);
  std::string error;
  ASSERT_TRUE(ring.prepare(k420, &error)) << error;
  auto planes = fillSlot(ring.source()->take(k420), 1);
  render::GpuCamera camera(*camera_, 64, 36);
  ASSERT_TRUE(camera.upload(render::SourceImage::yuv(planes), &error)) << error;
  ring.fenceCopy(*planes->slot);
  ring.reclaim();
  EXPECT_EQ(ring.occupancy().held, 1) << "held by the planes, whatever the fence says";
  planes.reset();
  EXPECT_EQ(ring.occupancy().copying, 1) << "released, but free only once reclaim saw its fence";
  EXPECT_FALSE(ring.source()->take(k420));
  glFinish();
  ring.reclaim();
  EXPECT_EQ(ring.occupancy().free, 1);
  EXPECT_TRUE(ring.source()->take(k420));
}

TEST_F(UploadRingTest, TexturesFromASlotHoldTheSameBytesAsFromOwnMemory) {
  for (const render::PlaneLayout layout : {k420, render::PlaneLayout{64, 36, 0, 0}}) {
    SCOPED_TRACE(layout.chroma_width == 0 ? "greyscale" : "4:2:0");
    render::UploadRing ring(2);
    std::string error;
    ASSERT_TRUE(ring.prepare(layout, &error)) << error;
    const auto in_slot = fillSlot(ring.source()->take(layout), 7);
    if (layout.chroma_width == 0) {
      EXPECT_FALSE(in_slot->slot->u);
    }
    const auto in_memory = ownCopy(*in_slot);
    render::GpuCamera from_slot(*camera_, 64, 36), from_memory(*camera_, 64, 36);
    ASSERT_TRUE(from_slot.upload(render::SourceImage::yuv(in_slot), &error)) << error;
    ring.fenceCopy(*in_slot->slot);
    ASSERT_TRUE(from_memory.upload(render::SourceImage::yuv(in_memory), &error)) << error;
    const std::vector<std::uint8_t> y = texture(from_slot, 0, layout.lumaBytes());
    EXPECT_EQ(y, texture(from_memory, 0, layout.lumaBytes()));
    EXPECT_TRUE(std::equal(y.begin(), y.end(), in_memory->y.begin()));
    if (layout.chroma_width > 0) {
      EXPECT_EQ(texture(from_slot, 1, layout.chromaBytes()), in_memory->u);
      EXPECT_EQ(texture(from_slot, 2, layout.chromaBytes()), in_memory->v);
    }
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    // The CPU's double reference reads the slot's bytes too.
    const Eigen::Vector2d px(10.3, 7.8);
    EXPECT_EQ(render::SourceImage::yuv(in_slot).sample(px), render::SourceImage::yuv(in_memory).sample(px));
  }
}

TEST_F(UploadRingTest, ASizeChangeRetiresTheOldBufferOnceItsSlotsAreBack) {
  render::UploadRing ring(2);
  std::string error;
  ASSERT_TRUE(ring.prepare(k420, &error)) << error;
  auto old_planes = fillSlot(ring.source()->take(k420), 3);
  const std::vector<std::uint8_t> old_bytes(old_planes->yPlane().begin(), old_planes->yPlane().end());
  const render::PlaneLayout bigger{128, 72, 64, 36};
  ASSERT_TRUE(ring.prepare(bigger, &error)) << error;
  EXPECT_TRUE(ring.preparedFor(bigger));
  EXPECT_FALSE(ring.source()->take(k420)) << "the old size is retired";
  const auto slot = ring.source()->take(bigger);
  ASSERT_TRUE(slot);
  EXPECT_NE(slot->buffer, old_planes->slot->buffer);
  ring.reclaim();
  EXPECT_TRUE(std::equal(old_bytes.begin(), old_bytes.end(), old_planes->yPlane().begin()))
      << "a held slot of the retired buffer stays readable";
  EXPECT_TRUE(glIsBuffer(old_planes->slot->buffer));
  const GLuint old_buffer = old_planes->slot->buffer;
  old_planes.reset();
  ring.reclaim();
  EXPECT_FALSE(glIsBuffer(old_buffer)) << "freed once its slots are back";
  EXPECT_EQ(ring.occupancy().held, 1);
}

TEST_F(UploadRingTest, PlanesHeldWhenTheRingGoesStayReadable) {
  std::shared_ptr<const render::YuvPlanes> planes;
  {
    render::UploadRing ring(1);
    std::string error;
    ASSERT_TRUE(ring.prepare(k420, &error)) << error;
    planes = fillSlot(ring.source()->take(k420), 9);
  }
  std::mt19937 rng(9);
  EXPECT_EQ(planes->yPlane()[0], std::uint8_t(rng()));
  planes.reset();  // gives the slot back to a source that outlived its ring: nothing to do
}

TEST_F(UploadRingTest, TheDecodePoolDecodesIntoSlotsAndFallsBackWhenNoneIsFree) {
  render::UploadRing ring(2);
  std::string error;
  const auto jpeg = test::texturedJpeg(64, 36, 11);
  const render::YuvPlanes reference = test::referenceDecode(jpeg);
  ASSERT_TRUE(ring.prepare(reference.layout(), &error)) << error;
  video::DecodePool pool(2);
  video::DecodeJob job;
  job.jpeg = jpeg;
  job.upload_slots = ring.source();
  const auto same = [&](const render::YuvPlanes& p) {
    return std::ranges::equal(p.yPlane(), reference.y) && std::ranges::equal(p.uPlane(), reference.u) &&
           std::ranges::equal(p.vPlane(), reference.v) && p.subsampling == reference.subsampling;
  };
  video::DecodeResult a = pool.submit(job).get();
  video::DecodeResult b = pool.submit(job).get();
  ASSERT_EQ(a.error, video::JpegDecodeError::kNone) << a.message;
  ASSERT_EQ(b.error, video::JpegDecodeError::kNone) << b.message;
  EXPECT_TRUE(a.in_upload_slot && a.planes->slot);
  EXPECT_TRUE(b.in_upload_slot && b.planes->slot);
  EXPECT_TRUE(same(*a.planes));
  EXPECT_TRUE(same(*b.planes));
  video::DecodeResult c = pool.submit(job).get();  // both slots held: the pool's own memory
  ASSERT_EQ(c.error, video::JpegDecodeError::kNone) << c.message;
  EXPECT_FALSE(c.in_upload_slot);
  EXPECT_FALSE(c.planes->slot);
  EXPECT_TRUE(same(*c.planes));
  EXPECT_EQ(ring.source()->counts().none_free, 1u);

  // A corrupt JPEG that fits a free slot: refused, and the slot is back.
  a.planes.reset();
  std::vector<std::uint8_t> corrupt = jpeg;
  corrupt.resize(corrupt.size() / 2);
  job.jpeg = corrupt;
  const video::DecodeResult d = pool.submit(job).get();
  EXPECT_EQ(d.error, video::JpegDecodeError::kCorrupt);
  EXPECT_FALSE(d.planes);
  EXPECT_EQ(ring.occupancy().free, 1) << "the slot the corrupt decode took is back";
  // A header the ring is not made for: the pool's memory, counted.
  const auto other = test::texturedJpeg(32, 18, 12);
  job.jpeg = other;
  const video::DecodeResult e = pool.submit(job).get();
  ASSERT_EQ(e.error, video::JpegDecodeError::kNone) << e.message;
  EXPECT_FALSE(e.in_upload_slot);
  EXPECT_GE(ring.source()->counts().other_layout, 1u);
}

}  // namespace
}  // namespace telesphere::xr
