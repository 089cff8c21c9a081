// SPDX-License-Identifier: MIT
/// @brief ControlQueue: one worker, requests in order.
#include "robot/link/control_queue.h"

namespace telesphere::link {

ControlQueue::ControlQueue(LinkClient& client, std::chrono::milliseconds timeout)
    : client_(client), timeout_(timeout), thread_([this] { run(); }) {}

ControlQueue::~ControlQueue() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    queue_.clear();
  }
  wake_.notify_all();
  thread_.join();
}

void ControlQueue::send(proto::ControlRequest request, Done done) {
  {
    std::lock_guard lock(mutex_);
    queue_.emplace_back(std::move(request), std::move(done));
  }
  wake_.notify_all();
}

void ControlQueue::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    auto [request, done] = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    const auto reply = client_.request(std::move(request), timeout_);
    if (done) done(reply);
    lock.lock();
  }
}

}  // namespace telesphere::link
