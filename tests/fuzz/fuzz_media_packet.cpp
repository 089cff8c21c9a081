// SPDX-License-Identifier: MIT
/// @brief libFuzzer target: what arrives on the media path. The first byte modulo 4 picks the part:
///        0: the rest is a sequence of datagrams, each behind a 2-byte big-endian length, fed
///        to a FrameAssembler (with a clock that advances, so frames are given up and filled;
///        with retransmission on when the first byte's bit 2 is set, asked after every datagram
///        for its repair requests);
///        1: the rest is a JPEG for findJpegBands, and every band found is filled;
///        2: datagrams as in 0, parsed as receiver reports and fed to a SendRateController that
///        sent datagrams 0..999 (the sender's side of the path);
///        3: the rest is one head-target datagram, and parsed as a repair request too (what the
///        robot takes from the operator). None
///        may crash, read out of bounds or hold more memory than its limits; every frame the
///        assembler delivers says its JPEGs' true sizes. (Whether a forged JPEG decodes is the
///        decoder's question, fuzzed in fuzz_jpeg_header.)
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "robot/link/media/frame_assembler.h"
#include "robot/link/media/head_target_datagram.h"
#include "robot/link/media/jpeg_bands.h"
#include "robot/link/media/receiver_report.h"
#include "robot/link/media/repair_request.h"
#include "robot/link/media/send_rate_controller.h"

namespace {

using namespace telesphere::link::media;

void fuzzAssembler(const std::uint8_t* data, std::size_t size, bool repair) {
  FrameAssembler::Config config;
  config.max_bytes_pending = 16u << 20;
  config.repair = repair;
  FrameAssembler assembler(config);
  std::vector<AssembledFrame> out;
  std::int64_t now = 0;
  std::size_t at = 0;
  while (at + 2 <= size) {
    const std::size_t n = std::size_t{data[at]} << 8 | data[at + 1];
    at += 2;
    const std::size_t take = n < size - at ? n : size - at;
    assembler.add({data + at, take}, now, out);
    if (const auto request = assembler.takeRepairRequest(now)) {
      if (!repair || request->chunks.empty() || request->chunks.size() > kMaxRepairChunks) std::abort();
      for (std::size_t i = 1; i < request->chunks.size(); ++i)
        if (request->chunks[i] <= request->chunks[i - 1]) std::abort();
    }
    at += take;
    now += 7'000'000;
    assembler.expire(now, out);
  }
  assembler.expire(now + 1'000'000'000, out);
  for (const AssembledFrame& f : out)
    if (f.stereo.left().jpeg_bytes() != f.left_jpeg.size() || f.stereo.right().jpeg_bytes() != f.right_jpeg.size())
      std::abort();
}

void fuzzBands(const std::uint8_t* data, std::size_t size) {
  std::string error;
  const auto bands = findJpegBands({data, size}, &error);
  if (!bands || bands->header_bytes > size) return;
  std::vector<std::uint8_t> out;
  for (std::size_t b = 0; b < bands->bands() && b < 64; ++b) {
    out.clear();
    if (!appendFillerBand({data, bands->header_bytes}, *bands, b, out, &error)) return;
  }
}

void fuzzReports(const std::uint8_t* data, std::size_t size) {
  SendRateController controller;
  for (std::uint32_t seq = 0; seq < 1000; ++seq) controller.onPacketSent(seq, std::int64_t{seq} * 100'000, 1228);
  ArrivalClock clock;
  std::int64_t now = 100'000'000;
  std::size_t at = 0;
  while (at + 2 <= size) {
    const std::size_t n = std::size_t{data[at]} << 8 | data[at + 1];
    at += 2;
    const std::size_t take = n < size - at ? n : size - at;
    MediaDropReason why{};
    if (const auto report = parseReceiverDatagram({data + at, take}, &why)) {
      std::vector<PacketReport> reports;
      for (const ReportEntry& e : report->entries) reports.push_back({e.seq, clock.unwrapNs(e.arrival_us)});
      controller.onFeedback(reports, now, report->entries.empty() ? -1 : report->hold_ns);
      if (!(controller.targetBps() > 0) || !(controller.stats().rtt_ms < 1e12)) std::abort();
    }
    at += take;
    now += 25'000'000;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  switch (data[0] % 4) {
    case 0: fuzzAssembler(data + 1, size - 1, (data[0] & 4) != 0); break;
    case 1: fuzzBands(data + 1, size - 1); break;
    case 2: fuzzReports(data + 1, size - 1); break;
    default: {
      MediaDropReason why{};
      if (const auto targets = parseHeadTargets({data + 1, size - 1}, &why))
        if (targets->empty() || targets->size() > 8) std::abort();
      if (const auto request = parseRepairRequest({data + 1, size - 1}, &why))
        for (std::size_t i = 1; i < request->chunks.size(); ++i)
          if (request->chunks[i] <= request->chunks[i - 1]) std::abort();
      break;
    }
  }
  return 0;
}
