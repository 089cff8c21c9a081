// SPDX-License-Identifier: MIT
/// @brief Head-target datagrams: writing and checked parsing.
#include "robot/link/media/head_target_datagram.h"

#include <algorithm>
#include <string>

namespace telesphere::link::media {
namespace {

constexpr std::size_t kMaxTargets = 8, kMaxTargetBytes = 400;

}  // namespace

void writeHeadTargets(std::span<const proto::HeadTarget> targets, std::vector<std::uint8_t>& out) {
  const std::size_t count = std::min(targets.size(), kMaxTargets);
  out.push_back(static_cast<std::uint8_t>(kMediaMagic >> 8));
  out.push_back(static_cast<std::uint8_t>(kMediaMagic & 0xFF));
  out.push_back(kMediaVersion);
  out.push_back(kHeadTargetsKind);
  out.insert(out.end(), {0, 0, static_cast<std::uint8_t>(count), 0});
  for (std::size_t i = targets.size() - count; i < targets.size(); ++i) {
    const std::string bytes = targets[i].SerializeAsString();
    out.push_back(static_cast<std::uint8_t>(bytes.size() >> 8));
    out.push_back(static_cast<std::uint8_t>(bytes.size() & 0xFF));
    out.insert(out.end(), bytes.begin(), bytes.end());
  }
}

std::optional<std::vector<proto::HeadTarget>> parseHeadTargets(std::span<const std::uint8_t> b, MediaDropReason* why) {
  const auto refuse = [&](MediaDropReason r) -> std::optional<std::vector<proto::HeadTarget>> {
    *why = r;
    return std::nullopt;
  };
  if (b.size() < kHeadTargetsHeaderBytes || (b[0] << 8 | b[1]) != kMediaMagic) return refuse(MediaDropReason::kMalformed);
  if (b[2] != kMediaVersion) return refuse(MediaDropReason::kWrongVersion);
  if (b[3] != kHeadTargetsKind || b[4] != 0 || b[5] != 0 || b[7] != 0 || b[6] == 0 || b[6] > kMaxTargets)
    return refuse(MediaDropReason::kMalformed);
  std::vector<proto::HeadTarget> targets(b[6]);
  std::size_t at = kHeadTargetsHeaderBytes;
  for (auto& target : targets) {
    if (at + 2 > b.size()) return refuse(MediaDropReason::kMalformed);
    const std::size_t n = static_cast<std::size_t>(b[at] << 8 | b[at + 1]);
    at += 2;
    if (n > kMaxTargetBytes || at + n > b.size() || !target.ParseFromArray(b.data() + at, static_cast<int>(n)))
      return refuse(MediaDropReason::kMalformed);
    at += n;
  }
  if (at != b.size()) return refuse(MediaDropReason::kMalformed);
  return targets;
}

}  // namespace telesphere::link::media
