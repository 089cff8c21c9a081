// SPDX-License-Identifier: MIT
/// @brief DecodePool: worker threads with one JpegDecoder each, and the plane recycler.
#include "xr/video/decode_pool.h"

#include <algorithm>
#include <chrono>

namespace telesphere::xr::video {

/// Plane sets no longer held by anyone, kept for reuse (at most kMaxFree of them).
struct DecodePool::Recycler {
  static constexpr std::size_t kMaxFree = 16;
  mutable std::mutex mutex;
  std::vector<std::unique_ptr<render::YuvPlanes>> free;
  std::uint64_t allocated = 0;

  std::unique_ptr<render::YuvPlanes> take() {
    std::lock_guard lock(mutex);
    if (free.empty()) {
      ++allocated;
      return std::make_unique<render::YuvPlanes>();
    }
    auto p = std::move(free.back());
    free.pop_back();
    return p;
  }

  void give(std::unique_ptr<render::YuvPlanes> p) {
    std::lock_guard lock(mutex);
    if (free.size() < kMaxFree) free.push_back(std::move(p));
  }

  /// Wraps p in a shared pointer that returns it here when the last holder lets go (or frees
  /// it when the pool is gone by then).
  static std::shared_ptr<const render::YuvPlanes> share(std::unique_ptr<render::YuvPlanes> p,
                                                const std::shared_ptr<Recycler>& recycler) {
    std::weak_ptr<Recycler> weak = recycler;
    return std::shared_ptr<const render::YuvPlanes>(p.release(), [weak](const render::YuvPlanes* raw) {
      std::unique_ptr<render::YuvPlanes> owned(const_cast<render::YuvPlanes*>(raw));
      if (auto r = weak.lock()) r->give(std::move(owned));
    });
  }
};

DecodePool::DecodePool(int threads) : recycler_(std::make_shared<Recycler>()) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  workers_.reserve(static_cast<std::size_t>(threads));
  for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

DecodePool::~DecodePool() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (auto& w : workers_) w.join();
}

std::future<DecodeResult> DecodePool::submit(DecodeJob job) {
  Task task{std::move(job), {}};
  std::future<DecodeResult> result = task.promise.get_future();
  {
    std::lock_guard lock(mutex_);
    queue_.push_back(std::move(task));
  }
  wake_.notify_one();
  return result;
}

std::uint64_t DecodePool::planesAllocated() const {
  std::lock_guard lock(recycler_->mutex);
  return recycler_->allocated;
}

std::size_t DecodePool::planesFree() const {
  std::lock_guard lock(recycler_->mutex);
  return recycler_->free.size();
}

bool DecodePool::decodeIntoSlot(JpegDecoder& decoder, const DecodeJob& job, DecodeResult& result) {
  if (!job.upload_slots) return false;
  JpegHeader header;
  result.error = decoder.readHeader(job.jpeg, job.expected_width, job.expected_height, job.max_side, &header,
                                    &result.message);
  if (result.error != JpegDecodeError::kNone) return true;  // refused: no memory of any kind needed
  auto slot = job.upload_slots->take(header.layout);
  if (!slot) return false;  // none free (or not this size): the pool's own memory
  auto planes = std::make_shared<render::YuvPlanes>();
  planes->width = header.layout.width;
  planes->height = header.layout.height;
  planes->chroma_width = header.layout.chroma_width;
  planes->chroma_height = header.layout.chroma_height;
  planes->subsampling = header.subsampling;
  result.error = decoder.decodeInto(job.jpeg, header, slot->y, slot->u, slot->v, &result.message);
  if (result.error != JpegDecodeError::kNone) return true;  // the slot goes back with `slot`
  planes->slot = std::move(slot);
  result.planes = std::move(planes);
  result.in_upload_slot = true;
  return true;
}

void DecodePool::work() {
  JpegDecoder decoder;
  for (;;) {
    Task task;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, and every queued job is done
      task = std::move(queue_.front());
      queue_.pop_front();
    }
    DecodeResult result;
    const auto t0 = std::chrono::steady_clock::now();
    // H.264/HEVC, or a JPEG with no upload slot free: into the pool's own planes.
    if (task.job.decode_into || !decodeIntoSlot(decoder, task.job, result)) {
      std::unique_ptr<render::YuvPlanes> planes = recycler_->take();
      if (task.job.decode_into)
        task.job.decode_into(*planes, result);
      else
        result.error = decoder.decode(task.job.jpeg, task.job.expected_width, task.job.expected_height,
                                      task.job.max_side, *planes, &result.message);
      if (result.error == JpegDecodeError::kNone)
        result.planes = Recycler::share(std::move(planes), recycler_);
      else
        recycler_->give(std::move(planes));
    }
    result.decode_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    task.job.keep_alive.reset();  // the bytes are no longer needed
    task.promise.set_value(std::move(result));
  }
}

}  // namespace telesphere::xr::video
