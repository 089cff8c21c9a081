// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench upload`: what a new 4K stereo camera frame costs the operator's render
///        thread, on the operator's own path minus the network (issue #16). Camera pairs arrive at
///        45 Hz as 4:2:0 JPEGs (as the robot sends them) and a DecodePool decodes them, two pairs
///        in flight; a render loop paced at 90 Hz takes the newest decoded pair at each frame's
///        start, uploads it, and draws both eyes (exact path, 1440×1600) to glFinish. Two ways:
///          - "upload ring": the pool decodes straight into the UploadRing's slots (GL buffer
///            memory); the render thread's GpuCamera::upload only queues the copies, then a fence;
///          - "decoder memory": the pool decodes into its own memory and GpuCamera::upload copies
///            2 × 12.4 MB in the call.
///        Per way: the render thread's ms in the upload (JSON upload_ms_render_thread_p50/_p99),
///        the frame's ms with and without a new image, decode ms, and the images that went through
///        the ring or the decoder's own memory. On llvmpipe every "GPU" copy is CPU work in the
///        call either way; only a GPU shows the ring's gain (xr/README.md).
#include <turbojpeg.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <future>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "calib/synthetic/typical_lenses.h"
#include "xr/render/spherical_renderer.h"
#include "xr/render/upload_ring.h"
#include "xr/video/decode_pool.h"

namespace telesphere::bench {
namespace {

constexpr int kCamWidth = calib::synthetic::kTypicalSensorWidthPx;    // 3840
constexpr int kCamHeight = calib::synthetic::kTypicalSensorHeightPx;  // 2160
constexpr double kCameraHz = 45.0;         // the paper's cameras
constexpr double kDisplayHz = 90.0;        // the render loop's pace (Vive Pro Eye)
constexpr int kEyeWidth = 1440, kEyeHeight = 1600;
constexpr int kPairsInFlight = 2;          // as StereoFrameDecoder
constexpr int kRingSlots = 10;             // StereoViewRenderer::kDefaultUploadSlots

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// A 4K camera image with structure at several scales and mild noise, so that the JPEG is about
/// as large as a real scene's (a smooth test pattern would decode unrealistically fast): about 0.8 MB
/// at quality 90 (the robot's default).
std::vector<std::uint8_t> cameraPicture(int variant) {
  std::vector<std::uint8_t> rgb(std::size_t(kCamWidth) * kCamHeight * 3);
  std::uint32_t noise = 0x9e3779b9u * std::uint32_t(variant + 1);
  for (int y = 0; y < kCamHeight; ++y)
    for (int x = 0; x < kCamWidth; ++x) {
      noise = noise * 1664525u + 1013904223u;
      const int n = int(noise >> 30) - 2;  // -2…+1 grey levels
      const bool check = ((x + 17 * variant) / 48 + y / 48) % 2 != 0;
      std::uint8_t* p = &rgb[(std::size_t(y) * kCamWidth + x) * 3];
      p[0] = std::uint8_t(std::clamp(x * 255 / kCamWidth + n, 0, 255));
      p[1] = std::uint8_t(std::clamp(y * 255 / kCamHeight + n, 0, 255));
      p[2] = std::uint8_t(std::clamp((check ? 200 : 40) + n, 0, 255));
    }
  return rgb;
}

std::vector<std::uint8_t> encodeJpeg420(const std::vector<std::uint8_t>& rgb, int quality) {
  tjhandle handle = tjInitCompress();
  if (!handle) throw std::runtime_error("TurboJPEG: no compressor");
  unsigned char* out = nullptr;
  unsigned long size = 0;
  const int rc = tjCompress2(handle, rgb.data(), kCamWidth, 0, kCamHeight, TJPF_RGB, &out, &size,
                             TJSAMP_420, quality, TJFLAG_FASTDCT);
  std::vector<std::uint8_t> jpeg;
  if (rc == 0) jpeg.assign(out, out + size);
  tjFree(out);
  tjDestroy(handle);
  if (rc != 0) throw std::runtime_error("TurboJPEG: could not encode the test image");
  return jpeg;
}

/// A stereo pair being decoded.
struct PairInFlight {
  std::future<xr::video::DecodeResult> left, right;
  bool ready() const {
    return left.wait_for(std::chrono::seconds(0)) == std::future_status::ready &&
           right.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
  }
};

/// Submits a pair to the pool every 1/45 s (at most kPairsInFlight undelivered; a camera frame
/// that finds them all busy is skipped, as the operator's decoder keeps only the newest).
class CameraFeed {
 public:
  CameraFeed(xr::video::DecodePool& pool, const std::vector<std::vector<std::uint8_t>>& jpegs,
             std::shared_ptr<xr::render::UploadSlotSource> slots)
      : pool_(pool), jpegs_(jpegs), slots_(std::move(slots)), thread_([this] { run(); }) {}
  ~CameraFeed() {
    stop_ = true;
    thread_.join();
  }
  /// The newest pair whose two images are decoded (older decoded ones dropped), if any.
  std::optional<PairInFlight> takeNewestReady() {
    std::lock_guard lock(mutex_);
    std::optional<PairInFlight> newest;
    while (!pending_.empty() && pending_.front().ready()) {
      newest = std::move(pending_.front());
      pending_.pop_front();
    }
    return newest;
  }
  int skipped() const { return skipped_; }

 private:
  void run() {
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / kCameraHz));
    auto next = Clock::now();
    for (std::size_t k = 0; !stop_; ++k, next += period) {
      std::this_thread::sleep_until(next);
      std::lock_guard lock(mutex_);
      if (int(pending_.size()) >= kPairsInFlight) {
        ++skipped_;
        continue;
      }
      PairInFlight pair;
      pair.left = pool_.submit(job(jpegs_[(2 * k) % jpegs_.size()]));
      pair.right = pool_.submit(job(jpegs_[(2 * k + 1) % jpegs_.size()]));
      pending_.push_back(std::move(pair));
    }
  }
  xr::video::DecodeJob job(const std::vector<std::uint8_t>& jpeg) const {
    xr::video::DecodeJob j;
    j.jpeg = jpeg;
    j.expected_width = kCamWidth;
    j.expected_height = kCamHeight;
    j.upload_slots = slots_;
    return j;
  }

  xr::video::DecodePool& pool_;
  const std::vector<std::vector<std::uint8_t>>& jpegs_;
  std::shared_ptr<xr::render::UploadSlotSource> slots_;
  std::mutex mutex_;
  std::deque<PairInFlight> pending_;
  std::atomic<bool> stop_{false};
  std::atomic<int> skipped_{0};
  std::thread thread_;  ///< last: starts once the rest is made
};

xr::render::EyeView eyeView(double side) {
  xr::render::EyeView view;
  view.fov = {side < 0 ? -0.96 : -0.82, side < 0 ? 0.82 : 0.96, 0.9, -0.92};
  view.width = kEyeWidth;
  view.height = kEyeHeight;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = xr::render::kR_optical_view;
  T.translation() << 0.032 * side, 0, 0;
  view.T_cam_eye = T;
  return view;
}

struct WayFigures {
  std::vector<double> upload_ms, frame_new_ms, frame_same_ms, decode_ms;
  int images_in_slots = 0, images_own = 0, frames = 0, skipped_camera_frames = 0;
};

/// One way: the render loop for `seconds` with the ring on (`ring_slots` > 0) or off.
WayFigures runWay(const calib::GenericCamera& camera, const std::vector<std::vector<std::uint8_t>>& jpegs,
                  int ring_slots, int pool_threads, double seconds) {
  std::string error;
  xr::render::UploadRing ring(ring_slots);  // first: outlives the planes that use its slots
  xr::render::SphericalRenderer renderer;
  std::array<xr::render::GpuCamera, 2> cameras{xr::render::GpuCamera(camera, kCamWidth, kCamHeight),
                                       xr::render::GpuCamera(camera, kCamWidth, kCamHeight)};
  for (auto& c : cameras)
    if (!renderer.prepare(c, xr::render::RenderPath::kExact, &error)) throw std::runtime_error(error);
  gl::OffscreenTarget target_l(kEyeWidth, kEyeHeight), target_r(kEyeWidth, kEyeHeight);
  const xr::render::EyeView view_l = eyeView(-1), view_r = eyeView(1);
  const xr::render::RenderSettings settings;

  WayFigures figures;
  std::array<std::shared_ptr<const xr::render::YuvPlanes>, 2> shown_planes;  // held while on show, as the renderer's frame
  {
    xr::video::DecodePool pool(pool_threads);
    CameraFeed feed(pool, jpegs, ring.source());
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / kDisplayHz));
    const auto start = Clock::now();
    auto next = start;
    while (Clock::now() - start < std::chrono::duration<double>(seconds)) {
      const auto t0 = Clock::now();
      ring.reclaim();
      bool new_image = false;
      if (auto pair = feed.takeNewestReady()) {
        std::array<xr::video::DecodeResult, 2> results{pair->left.get(), pair->right.get()};
        for (const auto& r : results) {
          if (r.error != xr::video::JpegDecodeError::kNone) throw std::runtime_error("decode: " + r.message);
          figures.decode_ms.push_back(r.decode_ms);
          (r.in_upload_slot ? figures.images_in_slots : figures.images_own) += 1;
        }
        if (ring.source() && !ring.prepare(results[0].planes->layout(), &error)) throw std::runtime_error(error);
        const auto tu = Clock::now();
        for (int i = 0; i < 2; ++i) {
          if (!cameras[std::size_t(i)].upload(xr::render::SourceImage::yuv(results[std::size_t(i)].planes), &error))
            throw std::runtime_error(error);
          if (results[std::size_t(i)].planes->slot) ring.fenceCopy(*results[std::size_t(i)].planes->slot);
        }
        figures.upload_ms.push_back(msSince(tu));
        for (int i = 0; i < 2; ++i) shown_planes[std::size_t(i)] = results[std::size_t(i)].planes;
        new_image = true;
      }
      if (shown_planes[0]) {
        if (!renderer.render(cameras[0], view_l, settings, target_l.framebuffer(), &error) ||
            !renderer.render(cameras[1], view_r, settings, target_r.framebuffer(), &error))
          throw std::runtime_error(error);
      }
      glFinish();
      if (shown_planes[0]) (new_image ? figures.frame_new_ms : figures.frame_same_ms).push_back(msSince(t0));
      ++figures.frames;
      next += period;
      if (next > Clock::now()) std::this_thread::sleep_until(next);
      else next = Clock::now();  // late: the next frame starts now (no burst to catch up)
    }
    figures.skipped_camera_frames = feed.skipped();
  }  // the feed stops, the pool finishes what it has (their planes are dropped)
  shown_planes = {};
  if (const GLenum e = glGetError(); e != GL_NO_ERROR)
    throw std::runtime_error("GL error " + std::to_string(e) + " during the upload benchmark");
  return figures;
}

nlohmann::json runUpload(const BenchContext& ctx) {
  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  if (!context) throw std::runtime_error("no OpenGL 4.5 context: " + error);
  const calib::GenericCamera camera(calib::DoubleSphereCamera<double>(
      calib::synthetic::TypicalLens<calib::DoubleSphereCamera>::parameters()));
  const double seconds = ctx.quick ? 4.0 : 10.0;
  const int pool_threads = std::clamp(int(std::thread::hardware_concurrency()), 2, 4);
  std::vector<std::vector<std::uint8_t>> jpegs;
  std::size_t jpeg_bytes = 0;
  for (int k = 0; k < 4; ++k) {  // two stereo pairs, alternated
    jpegs.push_back(encodeJpeg420(cameraPicture(k), 90));
    jpeg_bytes += jpegs.back().size();
  }

  Table table({"new image via", "frames", "frame ms p50 (new image)", "p99", "frame ms p50 (same image)",
               "upload ms render thread p50", "p99", "decode ms p50", "images ring / own", "camera frames skipped"});
  nlohmann::json json = {{"renderer", context->renderer()},
                         {"seconds_per_way", seconds},
                         {"eye", {kEyeWidth, kEyeHeight}},
                         {"camera_image", {kCamWidth, kCamHeight}},
                         {"jpeg_kb_mean", jpeg_bytes / 1e3 / double(jpegs.size())},
                         {"decode_threads", pool_threads}};
  const struct {
    const char* key;
    const char* name;
    int slots;
  } ways[] = {{"upload_ring", "upload ring of 10", kRingSlots}, {"decoder_memory", "decoder memory", 0}};
  for (const auto& way : ways) {
    const WayFigures f = runWay(camera, jpegs, way.slots, pool_threads, seconds);
    if (f.upload_ms.empty()) throw std::runtime_error("no camera frame was decoded in time");
    // Quantiles of what was seen; none (JSON null, "-") where no frame was of that kind (on llvmpipe
    // every frame finds a new image: rendering takes longer than a camera period).
    const auto q = [](const std::vector<double>& v, double p) {
      return v.empty() ? nlohmann::json(nullptr) : nlohmann::json(quantile(v, p));
    };
    const auto cell = [](const nlohmann::json& v) { return v.is_null() ? std::string("-") : formatNumber(v.get<double>()); };
    table.addRow({way.name, std::to_string(f.frames), cell(q(f.frame_new_ms, 0.5)),
                  cell(q(f.frame_new_ms, 0.99)), cell(q(f.frame_same_ms, 0.5)),
                  cell(q(f.upload_ms, 0.5)), cell(q(f.upload_ms, 0.99)),
                  cell(q(f.decode_ms, 0.5)),
                  std::to_string(f.images_in_slots) + " / " + std::to_string(f.images_own),
                  std::to_string(f.skipped_camera_frames)});
    json[way.key] = {{"frames", f.frames},
                     {"frame_ms_new_image_p50", q(f.frame_new_ms, 0.5)},
                     {"frame_ms_new_image_p99", q(f.frame_new_ms, 0.99)},
                     {"frame_ms_same_image_p50", q(f.frame_same_ms, 0.5)},
                     {"upload_ms_render_thread_p50", q(f.upload_ms, 0.5)},
                     {"upload_ms_render_thread_p99", q(f.upload_ms, 0.99)},
                     {"decode_ms_p50", q(f.decode_ms, 0.5)},
                     {"images_in_upload_slots", f.images_in_slots},
                     {"images_in_own_memory", f.images_own},
                     {"camera_frames_skipped", f.skipped_camera_frames}};
  }
  ctx.out << "A new 4K stereo camera frame on the render thread (" << context->renderer() << "): 2 x "
          << kCamWidth << "x" << kCamHeight << " JPEG 4:2:0 at " << kCameraHz << " Hz, "
          << formatNumber(json["jpeg_kb_mean"].get<double>()) << " kB each, decoded by " << pool_threads
          << " threads (" << kPairsInFlight << " pairs in flight); render loop paced at " << kDisplayHz
          << " Hz, both eyes " << kEyeWidth << "x" << kEyeHeight << " (exact path) to glFinish; "
          << seconds << " s per way:\n";
  table.print(ctx.out);
  return json;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(upload, telesphere::bench::BenchTopic{
                                   "upload",
                                   "a new 4K stereo camera frame's cost to the render thread: decoded "
                                   "into the upload ring (a copy command) vs from the decoder's memory",
                                   {},
                                   telesphere::bench::runUpload});
