// SPDX-License-Identifier: MIT
/// @brief Receiver reports and hellos: writing, checked parsing, unwrapping arrival stamps.
#include "robot/link/media/receiver_report.h"

#include "robot/link/media/big_endian.h"

#include <algorithm>

namespace telesphere::link::media {
using big_endian::get16;
using big_endian::get32;
using big_endian::put16;
using big_endian::put32;

void writeReceiverDatagram(const ReceiverDatagram& d, std::vector<std::uint8_t>& out) {
  const std::size_t n = d.hello ? 0 : std::min(d.entries.size(), kMaxReportEntries);
  put16(out, kMediaMagic);
  out.push_back(kMediaVersion);
  out.push_back(d.hello ? kReceiverHelloKind : kReceiverReportKind);
  put16(out, 0);
  put32(out, d.stream);
  put32(out, d.receiver);
  put16(out, static_cast<std::uint16_t>(n));
  const std::int64_t hold_100us = std::clamp<std::int64_t>((d.hold_ns + 50'000) / 100'000, 0, 0xFFFF);
  put16(out, static_cast<std::uint16_t>(hold_100us));
  for (std::size_t i = 0; i < n; ++i) {
    put32(out, d.entries[i].seq);
    put32(out, d.entries[i].arrival_us);
  }
}

std::optional<ReceiverDatagram> parseReceiverDatagram(std::span<const std::uint8_t> b, MediaDropReason* why) {
  const auto refuse = [&](MediaDropReason r) -> std::optional<ReceiverDatagram> {
    *why = r;
    return std::nullopt;
  };
  if (b.size() < kReceiverHeaderBytes || get16(b.data()) != kMediaMagic) return refuse(MediaDropReason::kMalformed);
  if (b[2] != kMediaVersion) return refuse(MediaDropReason::kWrongVersion);
  if ((b[3] != kReceiverReportKind && b[3] != kReceiverHelloKind) || get16(&b[4]) != 0)
    return refuse(MediaDropReason::kMalformed);
  ReceiverDatagram d;
  d.hello = b[3] == kReceiverHelloKind;
  d.stream = get32(&b[6]);
  d.receiver = get32(&b[10]);
  d.hold_ns = static_cast<std::int64_t>(get16(&b[16])) * 100'000;
  const std::size_t n = get16(&b[14]);
  if (n > kMaxReportEntries || b.size() != kReceiverHeaderBytes + 8 * n || (d.hello && n != 0) || d.receiver == 0)
    return refuse(MediaDropReason::kMalformed);
  d.entries.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = &b[kReceiverHeaderBytes + 8 * i];
    d.entries.push_back({get32(p), get32(p + 4)});
  }
  return d;
}

std::int64_t ArrivalClock::unwrapNs(std::uint32_t arrival_us) {
  if (!started_) {
    started_ = true;
    last_us_ = arrival_us;
    last_ns_ = 0;
    return 0;
  }
  // The stamps of one report round are close together: the signed difference unwraps them.
  const auto delta = static_cast<std::int32_t>(arrival_us - last_us_);
  last_us_ = arrival_us;
  last_ns_ += static_cast<std::int64_t>(delta) * 1000;
  return last_ns_;
}

}  // namespace telesphere::link::media
