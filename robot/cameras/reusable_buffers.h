// SPDX-License-Identifier: MIT
/// @brief Byte buffers handed out as shared pointers and reused once every holder has let go: a
///        4K stream then does not allocate (and page-fault in) megabytes per frame. For one
///        thread's use (the camera's stream thread, one encoder side); holders may release on any
///        thread.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace telesphere::robot::cameras {

class ReusableBuffers {
 public:
  /// Keeps up to `max_buffers`; when all are held, acquire() hands out a fresh one it does not keep.
  explicit ReusableBuffers(std::size_t max_buffers = 8) : max_buffers_(max_buffers) {}

  /// A buffer nobody else holds (its old contents and size kept: callers resize it).
  std::shared_ptr<std::vector<std::uint8_t>> acquire() {
    for (auto& buffer : buffers_) {
      if (buffer.use_count() == 1) {
        // The last other holder released it; order its reads before our writes.
        std::atomic_thread_fence(std::memory_order_acquire);
        return buffer;
      }
    }
    if (buffers_.size() < max_buffers_) return buffers_.emplace_back(std::make_shared<std::vector<std::uint8_t>>());
    return std::make_shared<std::vector<std::uint8_t>>();  // all in flight: a fresh one
  }

 private:
  std::size_t max_buffers_;
  std::vector<std::shared_ptr<std::vector<std::uint8_t>>> buffers_;
};

}  // namespace telesphere::robot::cameras
