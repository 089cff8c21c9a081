// SPDX-License-Identifier: MIT
/// @brief Envelope parsing and stereo-frame checks.
#include "robot/link/link_schema.h"

#include <random>

namespace telesphere::link {

std::uint64_t newLinkInstanceId() {
  std::random_device device;
  std::uint64_t id = 0;
  while (id == 0) id = (std::uint64_t{device()} << 32) ^ device();
  return id;
}

std::string_view dropReasonName(DropReason reason) {
  switch (reason) {
    case DropReason::kGarbage: return "garbage";
    case DropReason::kWrongSchemaVersion: return "wrong_schema_version";
    case DropReason::kUnexpectedBody: return "unexpected_body";
    case DropReason::kBadPartCount: return "bad_part_count";
    case DropReason::kBadImageSize: return "bad_image_size";
    case DropReason::kOversized: return "oversized";
    case DropReason::kSuperseded: return "superseded";
    case DropReason::kCorruptJpeg: return "corrupt_jpeg";
    case DropReason::kRefused: return "refused";
    case DropReason::kCount: break;
  }
  return "unknown";
}

std::optional<proto::Envelope> parseEnvelope(const void* data, std::size_t size, DropReason* why,
                                             std::uint32_t* peer_version, std::size_t max_bytes) {
  if (size > max_bytes) {
    *why = DropReason::kOversized;
    return std::nullopt;
  }
  proto::Envelope envelope;
  if (!envelope.ParseFromArray(data, static_cast<int>(size)) ||
      envelope.body_case() == proto::Envelope::BODY_NOT_SET) {
    *why = DropReason::kGarbage;
    return std::nullopt;
  }
  if (envelope.schema_version() != kSchemaVersion) {
    *why = DropReason::kWrongSchemaVersion;
    if (peer_version) *peer_version = envelope.schema_version();
    return std::nullopt;
  }
  return envelope;
}

namespace {
bool imageOk(const proto::CameraImage& image, std::size_t bytes) {
  return image.width() > 0 && image.height() > 0 && image.width() <= kMaxImageSide &&
         image.height() <= kMaxImageSide && image.jpeg_bytes() == bytes && bytes > 0;
}
}  // namespace

std::optional<DropReason> checkStereoFrame(const proto::StereoFrame& frame, std::size_t left_bytes,
                                           std::size_t right_bytes) {
  if (left_bytes > kMaxJpegBytes || right_bytes > kMaxJpegBytes) return DropReason::kOversized;
  if (!frame.has_left() || !frame.has_right() || !imageOk(frame.left(), left_bytes) ||
      !imageOk(frame.right(), right_bytes))
    return DropReason::kBadImageSize;
  return std::nullopt;
}

}  // namespace telesphere::link
