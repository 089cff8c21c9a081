// SPDX-License-Identifier: MIT
/// @brief Control requests without blocking the caller (a frame loop, a GUI thread): requests go
///        out one after another on a worker thread of their own, in the order given, each waiting
///        up to its timeout for the robot's reply; `done` is then called on that worker thread
///        with the reply, or with nothing when the robot did not answer in time.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

#include "robot/link/link_client.h"

namespace telesphere::link {

class ControlQueue {
 public:
  using Done = std::function<void(const std::optional<proto::ControlReply>&)>;

  /// `client` must outlive this object.
  explicit ControlQueue(LinkClient& client,
                        std::chrono::milliseconds timeout = std::chrono::milliseconds(2000));
  /// Waits for the request in flight (at most its timeout); requests not sent yet are dropped
  /// without their `done` being called.
  ~ControlQueue();
  ControlQueue(const ControlQueue&) = delete;
  ControlQueue& operator=(const ControlQueue&) = delete;

  void send(proto::ControlRequest request, Done done);

 private:
  void run();

  LinkClient& client_;
  std::chrono::milliseconds timeout_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::pair<proto::ControlRequest, Done>> queue_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace telesphere::link
