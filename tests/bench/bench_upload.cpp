// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench upload`: what a new 4K stereo frame costs the render thread, two ways
///        (issue #16). A decoded frame is 2 cameras × YUV 4:2:0 planes (3840×2160 Y, 2 × 1920×1080
///        chroma: 12.4 MB per camera). "client memory": six glTextureSubImage2D calls from the
///        decoder's own memory, as the operator view does today: the driver copies (or waits) in
///        the call. "PBO ring": the decoder writes into a persistently mapped pixel-unpack buffer
///        (a ring of three, each slot fenced so it is never written while the GL reads it) and
///        the render thread only issues the six copies from it plus a fence. Per way: the render
///        thread's ms, the ms until the copy is done on the GL side (glFinish, or the fence), and
///        for the ring the decoder-side memcpy into mapped memory. On a GPU the copy from a PBO
///        is a DMA the render thread does not wait for; on llvmpipe every "GPU" copy is CPU work,
///        so there only the render thread's share is meaningful.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "shaders/egl_context.h"
#include "shaders/gl_objects.h"
#include "tests/bench/bench_table.h"
#include "tests/bench/bench_topic.h"

namespace telesphere::bench {
namespace {

constexpr int kLumaWidth = 3840, kLumaHeight = 2160;
constexpr int kChromaWidth = kLumaWidth / 2, kChromaHeight = kLumaHeight / 2;
constexpr std::size_t kLumaBytes = std::size_t(kLumaWidth) * kLumaHeight;
constexpr std::size_t kChromaBytes = std::size_t(kChromaWidth) * kChromaHeight;
constexpr std::size_t kCameraBytes = kLumaBytes + 2 * kChromaBytes;
constexpr std::size_t kStereoBytes = 2 * kCameraBytes;
constexpr int kRingSlots = 3;

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Percentiles {
  double p50 = 0, p99 = 0;
};

Percentiles percentiles(const std::vector<double>& v) { return {quantile(v, 0.5), quantile(v, 0.99)}; }

/// One camera's three plane textures (R8), as GpuCamera allocates them for YUV input.
struct PlaneTextures {
  gl::GlTexture y, u, v;
  PlaneTextures() : y(texture(kLumaWidth, kLumaHeight)), u(texture(kChromaWidth, kChromaHeight)),
                    v(texture(kChromaWidth, kChromaHeight)) {}
  static gl::GlTexture texture(int w, int h) {
    gl::GlTexture t = gl::createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, GL_R8, w, h);
    return t;
  }
  /// The three copies from `base` (client pointer, or an offset into the bound unpack buffer).
  void copyFrom(const std::uint8_t* base) const {
    glTextureSubImage2D(y.id(), 0, 0, 0, kLumaWidth, kLumaHeight, GL_RED, GL_UNSIGNED_BYTE, base);
    glTextureSubImage2D(u.id(), 0, 0, 0, kChromaWidth, kChromaHeight, GL_RED, GL_UNSIGNED_BYTE, base + kLumaBytes);
    glTextureSubImage2D(v.id(), 0, 0, 0, kChromaWidth, kChromaHeight, GL_RED, GL_UNSIGNED_BYTE,
                        base + kLumaBytes + kChromaBytes);
  }
};

nlohmann::json runUpload(const BenchContext& ctx) {
  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  if (!context) throw std::runtime_error("no OpenGL 4.5 context: " + error);
  const int frames = ctx.quick ? 6 : 120;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);

  // Two decoded stereo frames in the decoder's memory, alternated so no copy is of the same bytes.
  std::vector<std::vector<std::uint8_t>> decoded(2, std::vector<std::uint8_t>(kStereoBytes));
  for (std::size_t k = 0; k < decoded.size(); ++k)
    for (std::size_t i = 0; i < kStereoBytes; ++i) decoded[k][i] = std::uint8_t((i * 31 + k * 97) >> 3);
  const PlaneTextures cam_l, cam_r;

  // (a) Client memory: the calls copy 2 × 12.4 MB before they return (or stall the pipeline).
  std::vector<double> sync_thread_ms, sync_done_ms;
  for (int i = -1; i < frames; ++i) {  // i = −1: warm-up
    const std::uint8_t* frame = decoded[std::size_t(i + 1) % 2].data();
    const auto t0 = Clock::now();
    cam_l.copyFrom(frame);
    cam_r.copyFrom(frame + kCameraBytes);
    const double thread_ms = msSince(t0);
    glFinish();
    if (i < 0) continue;
    sync_thread_ms.push_back(thread_ms);
    sync_done_ms.push_back(msSince(t0));
  }

  // (b) PBO ring: persistently mapped, coherent; the decoder writes slot k while the GL may still
  // read slot k−1; a slot is written again only after its fence signalled.
  gl::GlBuffer ring = gl::createBuffer();
  const GLsizeiptr ring_bytes = GLsizeiptr(kRingSlots * kStereoBytes);
  const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  glNamedBufferStorage(ring.id(), ring_bytes, nullptr, flags);
  auto* mapped = static_cast<std::uint8_t*>(glMapNamedBufferRange(ring.id(), 0, ring_bytes, flags));
  if (!mapped) throw std::runtime_error("glMapNamedBufferRange of a persistent 3 x 24.9 MB ring failed");
  std::vector<GLsync> fences(kRingSlots, nullptr);
  std::vector<double> ring_write_ms, ring_thread_ms, ring_done_ms;
  for (int i = -1; i < frames; ++i) {
    const int slot = (i + kRingSlots) % kRingSlots;
    std::uint8_t* dst = mapped + std::size_t(slot) * kStereoBytes;
    // Decoder side: wait until the GL no longer reads this slot, then write the frame into it.
    const auto tw = Clock::now();
    if (fences[std::size_t(slot)]) {
      glClientWaitSync(fences[std::size_t(slot)], GL_SYNC_FLUSH_COMMANDS_BIT, GLuint64(1e9));
      glDeleteSync(fences[std::size_t(slot)]);
      fences[std::size_t(slot)] = nullptr;
    }
    std::memcpy(dst, decoded[std::size_t(i + 1) % 2].data(), kStereoBytes);
    const double write_ms = msSince(tw);
    // Render thread: six copy commands from the buffer and a fence.
    const auto t0 = Clock::now();
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, ring.id());
    const auto* offset = reinterpret_cast<const std::uint8_t*>(std::uintptr_t(slot) * kStereoBytes);
    cam_l.copyFrom(offset);
    cam_r.copyFrom(offset + kCameraBytes);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    fences[std::size_t(slot)] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();
    const double thread_ms = msSince(t0);
    // Measured only: when the copies are done (the renderer would not wait here).
    glClientWaitSync(fences[std::size_t(slot)], GL_SYNC_FLUSH_COMMANDS_BIT, GLuint64(1e9));
    if (i < 0) continue;
    ring_write_ms.push_back(write_ms);
    ring_thread_ms.push_back(thread_ms);
    ring_done_ms.push_back(msSince(t0));
  }
  for (GLsync f : fences)
    if (f) glDeleteSync(f);
  glUnmapNamedBuffer(ring.id());
  if (const GLenum e = glGetError(); e != GL_NO_ERROR)
    throw std::runtime_error("GL error " + std::to_string(e) + " during the upload benchmark");

  const Percentiles st = percentiles(sync_thread_ms), sd = percentiles(sync_done_ms);
  const Percentiles rt = percentiles(ring_thread_ms), rd = percentiles(ring_done_ms), rw = percentiles(ring_write_ms);
  Table table({"way", "render thread ms p50", "p99", "copy done ms p50", "decoder-side write ms p50"});
  table.addRow({"client memory (glTextureSubImage2D)", formatNumber(st.p50), formatNumber(st.p99), formatNumber(sd.p50), "-"});
  table.addRow({"PBO ring (3 x persistent mapped)", formatNumber(rt.p50), formatNumber(rt.p99), formatNumber(rd.p50),
                formatNumber(rw.p50)});
  ctx.out << "A new 4K stereo frame (2 x YUV 4:2:0, " << formatNumber(kStereoBytes / 1e6) << " MB) on "
          << context->renderer() << ", " << frames << " frames:\n";
  table.print(ctx.out);
  return {{"renderer", context->renderer()},
          {"frames", frames},
          {"stereo_frame_mb", kStereoBytes / 1e6},
          {"client_memory", {{"render_thread_ms_p50", st.p50}, {"render_thread_ms_p99", st.p99}, {"done_ms_p50", sd.p50}}},
          {"pbo_ring",
           {{"render_thread_ms_p50", rt.p50}, {"render_thread_ms_p99", rt.p99}, {"done_ms_p50", rd.p50},
            {"decoder_write_ms_p50", rw.p50}}}};
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(upload, telesphere::bench::BenchTopic{
                                   "upload",
                                   "a new 4K stereo frame's cost to the render thread: client-memory "
                                   "texture upload vs a copy command from a persistently mapped PBO ring",
                                   {},
                                   telesphere::bench::runUpload});
