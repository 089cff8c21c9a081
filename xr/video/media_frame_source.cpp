// SPDX-License-Identifier: MIT
/// @brief MediaFrameSource: AssembledFrame → ReceivedFrame without copying the JPEGs.
#include "xr/video/media_frame_source.h"

namespace telesphere::xr::video {

std::unique_ptr<MediaFrameSource> MediaFrameSource::open(const std::string& host, int port, bool repair, bool sealed,
                                                         std::string* error) {
  link::media::MediaReceiverOptions options;
  options.assembler.repair = repair;
  options.sealed = sealed;
  options.sender_address = host;
  options.sender_port = static_cast<std::uint16_t>(port);
  auto receiver = link::media::MediaReceiver::start(options, error);
  if (!receiver) return nullptr;
  return std::unique_ptr<MediaFrameSource>(new MediaFrameSource(std::move(receiver)));
}

std::optional<link::ReceivedFrame> MediaFrameSource::waitFrame(std::chrono::milliseconds timeout) {
  auto assembled = receiver_->waitNewest(timeout);
  if (!assembled) return std::nullopt;
  auto storage = std::make_shared<link::media::AssembledFrame>(std::move(*assembled));
  link::ReceivedFrame r;
  r.frame = storage->stereo;
  // Received when its last datagram arrived (the link's steady clock, as the ZeroMQ client stamps).
  r.frame.mutable_stamps()->set_received_ns(storage->last_arrival_ns);
  r.left_jpeg = storage->left_jpeg;
  r.right_jpeg = storage->right_jpeg;
  for (const auto& rows : storage->left_lost) r.left_lost_rows.emplace_back(rows.first, rows.end);
  for (const auto& rows : storage->right_lost) r.right_lost_rows.emplace_back(rows.first, rows.end);
  r.storage = std::move(storage);
  return r;
}

}  // namespace telesphere::xr::video
