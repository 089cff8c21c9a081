// SPDX-License-Identifier: MIT
/// @brief What the media path's receiver sends back to the sender (DESIGN.md §9), in the media
///        datagram's family (same magic and version, its own kind):
///        - a report: the sequence number and arrival time (receiver's steady clock, µs,
///          wrapping) of every datagram of `stream` that arrived since the last report, up to
///          kMaxReportEntries per datagram; the send-rate controller's only input;
///        - a hello: "send to me", before the first frame and whenever no report is due. It
///          also carries the receiver's stream so a sender can tell a restarted receiver.
///        Layout, big-endian: magic u16, version u8, kind u8, reserved u16, stream u32,
///        receiver u32, count u16, hold u16, then count × (seq u32, arrival_us u32). hold: how
///        long the newest entry waited at the receiver before the report left, in 100 µs
///        (saturating at 6.5535 s), so the sender can take the report's wait out of its round trip.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "robot/link/media/media_packet.h"
#include "robot/link/media/send_rate_controller.h"

namespace telesphere::link::media {

inline constexpr std::uint8_t kReceiverReportKind = 2;
inline constexpr std::uint8_t kReceiverHelloKind = 3;
inline constexpr std::size_t kReceiverHeaderBytes = 18;
inline constexpr std::size_t kMaxReportEntries = (kMaxMediaDatagramBytes - kReceiverHeaderBytes) / 8;

struct ReportEntry {
  std::uint32_t seq = 0;
  std::uint32_t arrival_us = 0;  ///< receiver's steady clock, µs, wrapping every 71.6 min
};

struct ReceiverDatagram {
  bool hello = false;
  std::uint32_t stream = 0;    ///< the sender's stream reported on (0 in a hello before any frame)
  std::uint32_t receiver = 0;  ///< random per receiving process
  std::int64_t hold_ns = 0;    ///< the last entry's wait before the report left (100 µs steps on the wire)
  std::vector<ReportEntry> entries;
};

/// Appends one datagram; entries beyond kMaxReportEntries are not written (the caller splits).
void writeReceiverDatagram(const ReceiverDatagram& datagram, std::vector<std::uint8_t>& out);
/// A report or hello, or nothing (kMalformed, kWrongVersion) for anything else.
std::optional<ReceiverDatagram> parseReceiverDatagram(std::span<const std::uint8_t> bytes, MediaDropReason* why);

/// Turns wrapping µs arrival stamps into a monotonic ns clock (the first stamp is its zero).
class ArrivalClock {
 public:
  std::int64_t unwrapNs(std::uint32_t arrival_us);

 private:
  bool started_ = false;
  std::uint32_t last_us_ = 0;
  std::int64_t last_ns_ = 0;
};

}  // namespace telesphere::link::media
