// SPDX-License-Identifier: MIT
/// @brief A fixed pool of decode threads, each with its own JpegDecoder (a TurboJPEG handle is
///        not thread-safe), that decodes JPEGs to YUV planes (DESIGN.md §4). Results are shared,
///        immutable planes; when the last holder lets go of them their buffers go back to the
///        pool and the next decode of the same size reuses them (no allocation, no page faults
///        in steady state, and a bounded number of plane sets however slow the consumer is).
///        A job may name an UploadSlotSource: the planes then go straight into a free slot of GL
///        buffer memory (the render thread only queues a copy from it), and into the pool's own
///        memory only when no slot of that size is free.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "xr/video/jpeg_decoder.h"
#include "xr/render/upload_ring.h"

namespace telesphere::xr::video {

struct DecodeResult;

struct DecodeJob {
  std::span<const std::uint8_t> jpeg;  ///< must stay valid until the result is ready
  std::shared_ptr<const void> keep_alive;  ///< owner of the bytes (e.g. the link message); held until then
  int expected_width = 0;   ///< px, as the message said; 0 accepts any size
  int expected_height = 0;  ///< px
  int max_side = 8192;      ///< px; larger headers are refused before anything is allocated
  std::shared_ptr<render::UploadSlotSource> upload_slots;  ///< decode into a slot of it when one is free
  /// Set: the worker runs this instead of decoding `jpeg` (H.264/HEVC, VideoStreamDecoder): it
  /// fills the planes it is given (the pool's own memory, recycled like a JPEG's) and the result's
  /// error and message.
  std::function<void(render::YuvPlanes& planes, DecodeResult& result)> decode_into;
};

struct DecodeResult {
  JpegDecodeError error = JpegDecodeError::kNone;
  std::string message;                      ///< why, when error != kNone
  std::shared_ptr<const render::YuvPlanes> planes;  ///< set when error == kNone
  double decode_ms = 0;                     ///< wall time of the decode on its worker
  bool in_upload_slot = false;              ///< the planes are in GL buffer memory (planes->slot)
  /// H.264/HEVC: refused because a frame before it was lost (error kCorrupt): the stream's decoder
  /// waits for a key frame.
  bool awaiting_key_frame = false;
};

class DecodePool {
 public:
  /// threads ≤ 0: std::thread::hardware_concurrency() (at least 1).
  explicit DecodePool(int threads = 0);
  /// Finishes the jobs already submitted, then joins the workers.
  ~DecodePool();
  DecodePool(const DecodePool&) = delete;
  DecodePool& operator=(const DecodePool&) = delete;

  /// Queues a decode; the future becomes ready when a worker has done it.
  std::future<DecodeResult> submit(DecodeJob job);

  int threads() const { return static_cast<int>(workers_.size()); }
  /// Plane sets ever allocated (recycled ones not counted again): stays bounded in steady state.
  std::uint64_t planesAllocated() const;
  /// Plane sets waiting for reuse now.
  std::size_t planesFree() const;

 private:
  struct Task {
    DecodeJob job;
    std::promise<DecodeResult> promise;
  };
  struct Recycler;

  void work();
  /// Decodes into a slot of job.upload_slots when one of the image's size is free; false (nothing
  /// done) when there is no such slot. True with the result otherwise, errors included.
  static bool decodeIntoSlot(JpegDecoder& decoder, const DecodeJob& job, DecodeResult& result);

  std::shared_ptr<Recycler> recycler_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Task> queue_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace telesphere::xr::video
