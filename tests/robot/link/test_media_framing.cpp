// SPDX-License-Identifier: MIT
/// @brief The media datagram and the frame assembler: headers round-trip and refuse what does
///        not add up; stereo frames of real JPEGs come back byte-identical in any order, with
///        duplicates; a lost chunk costs the bands it held (filled grey, the JPEG valid, every
///        other pixel identical), a lost meta costs the frame unless its repeat arrives; latest
///        wins; a restarted sender is taken over; memory stays bounded under forged frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "robot/link/media/frame_assembler.h"
#include "robot/link/media/frame_packetizer.h"
#include "robot/link/media/head_target_datagram.h"
#include "robot/link/media/jpeg_bands.h"
#include "robot/link/media/receiver_report.h"
#include "robot/link/media/repair_request.h"
#include "tests/robot/link/media_test_jpegs.h"

namespace telesphere::link::media {
namespace {

constexpr std::int64_t kMs = 1'000'000;

MediaPacketHeader sampleHeader() {
  MediaPacketHeader h;
  h.flags = MediaPacketHeader::kFlagRepeat;
  h.stream = 0xDEADBEEF;
  h.packet_seq = 0xFFFFFFFF;
  h.send_us = 123456789;
  h.frame = 0x80000001;
  h.frame_bytes = 3000;
  h.chunk_index = 2;
  h.chunk_bytes = 1200;
  h.meta_bytes = 100;
  return h;
}

TEST(MediaPacket, HeaderRoundTripsAndStampsInPlace) {
  const MediaPacketHeader h = sampleHeader();
  const std::vector<std::uint8_t> payload(600, 7);  // 3000 - 2 × 1200
  std::vector<std::uint8_t> d;
  writeMediaPacket(h, payload, d);
  ASSERT_EQ(d.size(), kMediaHeaderBytes + payload.size());
  MediaDropReason why{};
  auto v = parseMediaPacket(d, &why);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->header.stream, h.stream);
  EXPECT_EQ(v->header.packet_seq, h.packet_seq);
  EXPECT_EQ(v->header.send_us, h.send_us);
  EXPECT_EQ(v->header.frame, h.frame);
  EXPECT_EQ(v->header.frame_bytes, h.frame_bytes);
  EXPECT_EQ(v->header.chunk_index, h.chunk_index);
  EXPECT_EQ(v->header.chunk_bytes, h.chunk_bytes);
  EXPECT_EQ(v->header.meta_bytes, h.meta_bytes);
  EXPECT_EQ(v->header.flags, h.flags);
  EXPECT_TRUE(std::equal(v->payload.begin(), v->payload.end(), payload.begin(), payload.end()));
  stampForSending(d, 42, 4'000'000'000u);
  v = parseMediaPacket(d, &why);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->header.packet_seq, 42u);
  EXPECT_EQ(v->header.send_us, 4'000'000'000u);
}

TEST(MediaPacket, RefusesFieldsThatDoNotAddUp) {
  const auto parsed = [](MediaPacketHeader h, std::size_t payload_bytes, MediaDropReason expected) {
    std::vector<std::uint8_t> d;
    writeMediaPacket(h, std::vector<std::uint8_t>(payload_bytes), d);
    MediaDropReason why{};
    EXPECT_FALSE(parseMediaPacket(d, &why));
    EXPECT_EQ(why, expected) << mediaDropReasonName(why);
  };
  MediaPacketHeader h = sampleHeader();
  parsed(h, 599, MediaDropReason::kMalformed);   // a payload one byte short of what the fields say
  parsed(h, 601, MediaDropReason::kMalformed);
  h.chunk_index = 3;  // beyond the last chunk
  parsed(h, 0, MediaDropReason::kMalformed);
  h = sampleHeader();
  h.meta_bytes = 0;
  parsed(h, 600, MediaDropReason::kMalformed);
  h = sampleHeader();
  h.meta_bytes = 3001;
  parsed(h, 600, MediaDropReason::kMalformed);
  h = sampleHeader();
  h.chunk_bytes = kMaxChunkBytes + 1;
  parsed(h, 0, MediaDropReason::kMalformed);
  h = sampleHeader();
  h.frame_bytes = kMaxMediaFrameBytes + 1;
  parsed(h, 600, MediaDropReason::kTooLarge);
  h = sampleHeader();
  h.flags = 2;
  parsed(h, 600, MediaDropReason::kMalformed);
  h = sampleHeader();
  h.chunk_index = 0;
  parsed(h, kMaxMediaDatagramBytes - kMediaHeaderBytes + 1, MediaDropReason::kTooLarge);  // a datagram beyond the limit
  // Parity shards: an index past its block's, a block past the frame's chunks, a short shard.
  h = sampleHeader();
  h.kind = MediaPacketKind::kFrameParity;
  h.flags = 0;
  h.chunk_index = 0;
  h.fec_k = 3;
  h.fec_r = 1;
  h.fec_j = 0;
  {
    std::vector<std::uint8_t> d;
    writeMediaPacket(h, std::vector<std::uint8_t>(1200), d);
    MediaDropReason why{};
    const auto v = parseMediaPacket(d, &why);
    ASSERT_TRUE(v) << mediaDropReasonName(why);
    EXPECT_EQ(v->header.fec_k, 3);
    EXPECT_EQ(v->payload.size(), 1200u);
  }
  h.fec_j = 1;
  parsed(h, 1200, MediaDropReason::kMalformed);
  h.fec_j = 0;
  h.fec_k = 4;  // chunks 0..3 of a 3-chunk frame
  parsed(h, 1200, MediaDropReason::kMalformed);
  h.fec_k = 3;
  parsed(h, 600, MediaDropReason::kMalformed);

  std::vector<std::uint8_t> d;
  writeMediaPacket(sampleHeader(), std::vector<std::uint8_t>(600), d);
  MediaDropReason why{};
  auto bad = d;
  bad[2] = 2;
  EXPECT_FALSE(parseMediaPacket(bad, &why));
  EXPECT_EQ(why, MediaDropReason::kWrongVersion);
  bad = d;
  bad[0] = 'X';
  EXPECT_FALSE(parseMediaPacket(bad, &why));
  EXPECT_EQ(why, MediaDropReason::kMalformed);
  for (std::size_t n = 0; n < kMediaHeaderBytes; ++n) {
    EXPECT_FALSE(parseMediaPacket({d.data(), n}, &why));
    EXPECT_EQ(why, MediaDropReason::kMalformed);
  }
}

TEST(ReceiverReport, RoundTripsSplitsAtTheLimitAndRefusesWhatDoesNotAddUp) {
  ReceiverDatagram report;
  report.stream = 0xABCDEF01;
  report.receiver = 77;
  report.hold_ns = 12'345'678;  // 12.35 ms: the wire carries 100 µs steps
  for (std::uint32_t i = 0; i < kMaxReportEntries + 5; ++i) report.entries.push_back({0xFFFFFFF0u + i, i * 1000});
  std::vector<std::uint8_t> bytes;
  writeReceiverDatagram(report, bytes);
  ASSERT_LE(bytes.size(), kMaxMediaDatagramBytes);
  MediaDropReason why{};
  auto parsed = parseReceiverDatagram(bytes, &why);
  ASSERT_TRUE(parsed);
  EXPECT_FALSE(parsed->hello);
  EXPECT_EQ(parsed->stream, report.stream);
  EXPECT_EQ(parsed->receiver, 77u);
  EXPECT_EQ(parsed->hold_ns, 12'300'000);
  ASSERT_EQ(parsed->entries.size(), kMaxReportEntries) << "the rest goes in the next datagram";
  EXPECT_EQ(parsed->entries.back().seq, static_cast<std::uint32_t>(0xFFFFFFF0u + kMaxReportEntries - 1));
  EXPECT_EQ(parsed->entries.back().arrival_us, static_cast<std::uint32_t>((kMaxReportEntries - 1) * 1000));

  ReceiverDatagram hello;
  hello.hello = true;
  hello.receiver = 5;
  bytes.clear();
  writeReceiverDatagram(hello, bytes);
  parsed = parseReceiverDatagram(bytes, &why);
  ASSERT_TRUE(parsed);
  EXPECT_TRUE(parsed->hello);
  EXPECT_TRUE(parsed->entries.empty());

  auto refused = [&](std::vector<std::uint8_t> b, MediaDropReason expected) {
    EXPECT_FALSE(parseReceiverDatagram(b, &why));
    EXPECT_EQ(why, expected) << mediaDropReasonName(why);
  };
  bytes.clear();
  report.entries.resize(3);
  writeReceiverDatagram(report, bytes);
  refused(std::vector<std::uint8_t>(bytes.begin(), bytes.end() - 1), MediaDropReason::kMalformed);  // a torn entry
  auto b = bytes;
  b[15] = 4;  // says 4 entries, holds 3
  refused(b, MediaDropReason::kMalformed);
  b = bytes;
  b[3] = 1;  // a frame chunk's kind
  refused(b, MediaDropReason::kMalformed);
  b = bytes;
  b[2] = 9;
  refused(b, MediaDropReason::kWrongVersion);
  b = bytes;
  b[10] = b[11] = b[12] = b[13] = 0;  // receiver 0
  refused(b, MediaDropReason::kMalformed);
  refused({}, MediaDropReason::kMalformed);

  // A hold beyond what 16 bits of 100 µs hold saturates at 6.5535 s; a negative one is 0.
  for (const auto& [hold_ns, expected_ns] : {std::pair<std::int64_t, std::int64_t>{60'000'000'000, 6'553'500'000},
                                             {-5, 0}, {49'999, 0}, {50'000, 100'000}}) {
    report.hold_ns = hold_ns;
    bytes.clear();
    writeReceiverDatagram(report, bytes);
    parsed = parseReceiverDatagram(bytes, &why);
    ASSERT_TRUE(parsed);
    EXPECT_EQ(parsed->hold_ns, expected_ns) << hold_ns;
  }
}

TEST(RepairRequest, RoundTripsAndRefusesWhatDoesNotAddUp) {
  RepairRequest r;
  r.stream = 0x01020304;
  r.receiver = 9;
  r.frame = 0xFFFFFFFE;
  for (std::uint16_t c = 0; c < kMaxRepairChunks + 3; ++c) r.chunks.push_back(static_cast<std::uint16_t>(3 * c));
  std::vector<std::uint8_t> bytes;
  writeRepairRequest(r, bytes);
  ASSERT_LE(bytes.size(), kMaxMediaDatagramBytes);
  MediaDropReason why{};
  auto parsed = parseRepairRequest(bytes, &why);
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->stream, r.stream);
  EXPECT_EQ(parsed->receiver, 9u);
  EXPECT_EQ(parsed->frame, 0xFFFFFFFEu);
  ASSERT_EQ(parsed->chunks.size(), kMaxRepairChunks) << "the rest does not fit one datagram";
  EXPECT_EQ(parsed->chunks.back(), 3 * (kMaxRepairChunks - 1));

  r.chunks = {4, 9};
  bytes.clear();
  writeRepairRequest(r, bytes);
  const auto refused = [&](std::vector<std::uint8_t> b, MediaDropReason expected) {
    EXPECT_FALSE(parseRepairRequest(b, &why));
    EXPECT_EQ(why, expected) << mediaDropReasonName(why);
  };
  refused({bytes.begin(), bytes.end() - 1}, MediaDropReason::kMalformed);  // a torn chunk index
  auto b = bytes;
  b[25] = 3;  // 4, 3: not ascending
  refused(b, MediaDropReason::kMalformed);
  b = bytes;
  b[19] = 0;  // no chunks, yet two are there
  refused(b, MediaDropReason::kMalformed);
  b = bytes;
  b[10] = b[11] = b[12] = b[13] = 0;  // receiver 0
  refused(b, MediaDropReason::kMalformed);
  b = bytes;
  b[2] = 2;
  refused(b, MediaDropReason::kWrongVersion);
  b = bytes;
  b[3] = kReceiverReportKind;
  refused(b, MediaDropReason::kMalformed);
}

TEST(HeadTargetDatagram, CarriesTheLastFewTargetsAndRefusesWhatDoesNotAddUp) {
  std::vector<proto::HeadTarget> targets(3);
  for (int i = 0; i < 3; ++i) {
    targets[static_cast<std::size_t>(i)].set_t_ns(1000 + i);
    targets[static_cast<std::size_t>(i)].set_valid(true);
    targets[static_cast<std::size_t>(i)].set_sender_instance(77);
    targets[static_cast<std::size_t>(i)].mutable_t_vr_hmd()->set_qw(1.0);
  }
  std::vector<std::uint8_t> bytes;
  writeHeadTargets(targets, bytes);
  EXPECT_LT(bytes.size(), 400u);
  MediaDropReason why{};
  auto parsed = parseHeadTargets(bytes, &why);
  ASSERT_TRUE(parsed);
  ASSERT_EQ(parsed->size(), 3u);
  EXPECT_EQ((*parsed)[2].t_ns(), 1002);
  EXPECT_EQ((*parsed)[0].sender_instance(), 77u);
  const auto refused = [&](std::vector<std::uint8_t> b) {
    EXPECT_FALSE(parseHeadTargets(b, &why));
    return why;
  };
  EXPECT_EQ(refused(std::vector<std::uint8_t>(bytes.begin(), bytes.end() - 1)), MediaDropReason::kMalformed);
  auto extra = bytes;
  extra.push_back(0);
  EXPECT_EQ(refused(extra), MediaDropReason::kMalformed) << "trailing bytes";
  auto zero = bytes;
  zero[6] = 0;
  EXPECT_EQ(refused(zero), MediaDropReason::kMalformed);
  auto version = bytes;
  version[2] = 7;
  EXPECT_EQ(refused(version), MediaDropReason::kWrongVersion);
  auto garbage = bytes;
  garbage[kHeadTargetsHeaderBytes + 2] = 0xFF;  // the first target's protobuf
  garbage[kHeadTargetsHeaderBytes + 3] = 0xFF;
  EXPECT_EQ(refused(garbage), MediaDropReason::kMalformed);
}

TEST(ReceiverReport, ArrivalStampsUnwrapAcrossTheirWrap) {
  ArrivalClock clock;
  EXPECT_EQ(clock.unwrapNs(0xFFFFFF00u), 0);
  EXPECT_EQ(clock.unwrapNs(0xFFFFFFFFu), 255'000);
  EXPECT_EQ(clock.unwrapNs(0x00000010u), 272'000);  // wrapped: 17 µs later
  EXPECT_EQ(clock.unwrapNs(0x00000008u), 264'000);  // a stamp slightly older (reordered)
}

/// A stereo frame of two real JPEGs (restart every MCU row), and what the packetizer made of it.
struct SentFrame {
  proto::StereoFrame stereo;
  std::vector<std::uint8_t> left, right;
  PacketizedFrame packets;
};

SentFrame sendFrame(FramePacketizer& packetizer, int width, int height, int seed, std::uint64_t sequence) {
  SentFrame f;
  f.left = test::encodeJpeg(width, height, ChromaSubsampling::k420, 1, 85, seed);
  f.right = test::encodeJpeg(width, height, ChromaSubsampling::k420, 1, 85, seed + 1000);
  f.stereo.set_sequence(sequence);
  for (auto* image : {f.stereo.mutable_left(), f.stereo.mutable_right()}) {
    image->set_width(static_cast<std::uint32_t>(width));
    image->set_height(static_cast<std::uint32_t>(height));
    image->set_capture_ns(1000 + static_cast<std::int64_t>(sequence));
  }
  f.stereo.mutable_stamps()->set_sent_ns(77);
  std::string error;
  EXPECT_TRUE(packetizer.packetize(f.stereo, f.left, f.right, &f.packets, &error)) << error;
  f.stereo.mutable_left()->set_jpeg_bytes(static_cast<std::uint32_t>(f.left.size()));
  f.stereo.mutable_right()->set_jpeg_bytes(static_cast<std::uint32_t>(f.right.size()));
  return f;
}

/// The frame's chunks, once each, in order: no repeats, no parity.
std::vector<std::vector<std::uint8_t>> withoutRepeats(const PacketizedFrame& p) {
  std::vector<std::vector<std::uint8_t>> out;
  for (const auto& d : p.datagrams)
    if ((d[4] & MediaPacketHeader::kFlagRepeat) == 0 && d[3] == static_cast<std::uint8_t>(MediaPacketKind::kFrameChunk))
      out.push_back(d);
  return out;
}

TEST(FrameAssembler, WholeFramesComeBackByteIdenticalInAnyOrderWithDuplicates) {
  FramePacketizer packetizer(0x1234, {});
  const SentFrame sent = sendFrame(packetizer, 320, 240, 1, 5);
  ASSERT_GT(sent.packets.datagrams.size(), 10u);
  for (int order = 0; order < 3; ++order) {
    SCOPED_TRACE("order " + std::to_string(order));
    auto datagrams = withoutRepeats(sent.packets);
    std::mt19937 rng(static_cast<unsigned>(order));
    if (order == 1) std::reverse(datagrams.begin(), datagrams.end());
    if (order == 2) {
      std::shuffle(datagrams.begin(), datagrams.end(), rng);
      datagrams.insert(datagrams.begin() + 3, datagrams[1]);  // a duplicate before the frame completes
    }
    FrameAssembler assembler;
    std::vector<AssembledFrame> out;
    for (const auto& d : datagrams) assembler.add(d, 0, out);
    ASSERT_EQ(out.size(), 1u);
    const AssembledFrame& f = out[0];
    EXPECT_TRUE(f.whole());
    EXPECT_EQ(f.stream, 0x1234u);
    EXPECT_EQ(f.frame, sent.packets.frame);
    EXPECT_EQ(f.left_jpeg, sent.left);
    EXPECT_EQ(f.right_jpeg, sent.right);
    EXPECT_EQ(f.stereo.SerializeAsString(), sent.stereo.SerializeAsString());
    EXPECT_EQ(assembler.stats().frames_whole, 1u);
    EXPECT_EQ(assembler.stats().dropped(MediaDropReason::kDuplicate), order == 2 ? 1u : 0u);
    EXPECT_EQ(assembler.framesPending(), 0u);
  }
}

TEST(FrameAssembler, ALostChunkCostsItsBandsFilledGreyEverythingElseIntact) {
  FramePacketizer packetizer(7, {});
  const SentFrame sent = sendFrame(packetizer, 640, 480, 2, 1);
  const auto datagrams = withoutRepeats(sent.packets);
  std::string error;
  const auto left_bands = findJpegBands(sent.left, &error);
  ASSERT_TRUE(left_bands) << error;
  // Lose the chunk holding the middle of the left image's band 10.
  const std::size_t meta_bytes = sent.packets.frame_bytes - sent.left.size() - sent.right.size();
  const std::size_t lost_byte = meta_bytes + left_bands->bandOffset(10) + left_bands->band_bytes[10] / 2;
  const std::size_t lost_chunk = lost_byte / kMaxChunkBytes;
  FrameAssembler assembler;
  std::vector<AssembledFrame> out;
  for (std::size_t i = 0; i < datagrams.size(); ++i)
    if (i != lost_chunk) assembler.add(datagrams[i], static_cast<std::int64_t>(i) * kMs / 10, out);
  EXPECT_TRUE(out.empty()) << "an incomplete frame is held until its grace passes";
  assembler.expire(20 * kMs, out);
  EXPECT_TRUE(out.empty());
  assembler.expire(200 * kMs, out);
  ASSERT_EQ(out.size(), 1u);
  const AssembledFrame& f = out[0];
  EXPECT_FALSE(f.whole());
  EXPECT_EQ(f.chunks_missing, 1u);
  EXPECT_EQ(f.right_jpeg, sent.right);
  EXPECT_TRUE(f.right_lost.empty());
  // The bands the chunk touched, and only those.
  const std::size_t chunk_begin = lost_chunk * kMaxChunkBytes - meta_bytes;
  const std::size_t chunk_end = chunk_begin + kMaxChunkBytes;
  std::vector<LostRows> expected;
  std::uint32_t bands_touched = 0;
  for (std::size_t b = 0; b < left_bands->bands(); ++b) {
    const std::size_t begin = left_bands->bandOffset(b), end = begin + left_bands->band_bytes[b];
    if (begin < chunk_end && end > chunk_begin) {
      ++bands_touched;
      const auto rows = left_bands->bandRows(b);
      if (!expected.empty() && expected.back().end == rows.first) expected.back().end = rows.second;
      else expected.push_back({rows.first, rows.second});
    }
  }
  EXPECT_EQ(f.left_lost, expected);
  EXPECT_EQ(f.bands_lost, bands_touched);
  EXPECT_EQ(assembler.stats().bands_lost, bands_touched);
  EXPECT_EQ(assembler.stats().frames_concealed, 1u);
  EXPECT_EQ(f.stereo.left().jpeg_bytes(), f.left_jpeg.size());
  const test::Planes original = test::decodePlanes(sent.left), got = test::decodePlanes(f.left_jpeg);
  ASSERT_TRUE(got.ok) << "the assembled JPEG must decode without a warning";
  for (int y = 0; y < 480; ++y) {
    const bool lost = std::any_of(expected.begin(), expected.end(), [&](const LostRows& r) { return y >= r.first && y < r.end; });
    for (int x = 0; x < 640; x += 7) {
      const std::size_t i = static_cast<std::size_t>(y) * 640 + x;
      if (lost) {
        ASSERT_EQ(got.y[i], 128);
      } else {
        ASSERT_EQ(got.y[i], original.y[i]);
      }
    }
  }
  // A chunk of that frame arriving now is late.
  assembler.add(datagrams[lost_chunk], 300 * kMs, out);
  EXPECT_EQ(assembler.stats().dropped(MediaDropReason::kLate), 1u);
}

TEST(FrameAssembler, TheMetaChunkLostCostsTheFrameUnlessItsRepeatArrives) {
  for (bool repeat : {true, false}) {
    SCOPED_TRACE(repeat ? "repeated headers" : "no repeats");
    FramePacketizer packetizer(9, {kMaxChunkBytes, 0.0, 16, repeat});
    const SentFrame sent = sendFrame(packetizer, 320, 240, 3, 1);
    FrameAssembler assembler;
    std::vector<AssembledFrame> out;
    for (std::size_t i = 1; i < sent.packets.datagrams.size(); ++i) assembler.add(sent.packets.datagrams[i], 0, out);
    assembler.expire(100 * kMs, out);
    if (repeat) {
      ASSERT_EQ(out.size(), 1u);
      EXPECT_TRUE(out[0].whole());
      EXPECT_EQ(assembler.stats().repeats_used, 1u);
      // The right header's repeat comes after the frame is whole: late, not held.
      const std::size_t repeats = sent.packets.datagrams.size() - withoutRepeats(sent.packets).size();
      EXPECT_GE(repeats, 2u);
      EXPECT_EQ(assembler.stats().dropped(MediaDropReason::kLate), repeats - 1);
    } else {
      EXPECT_TRUE(out.empty());
      EXPECT_EQ(assembler.stats().frames_lost, 1u);
    }
  }
}

// H.264/HEVC (#34): an access unit has no bands, so the packetizer takes any bytes (no JPEG
// scan) and the assembler delivers the frame whole or not at all: a predicted image with a hole
// would smear every image after it. Parity still rebuilds what it can.
TEST(FrameAssembler, AnH264FrameComesWholeOrNotAtAll) {
  SentFrame sent;
  sent.left.resize(9000);
  sent.right.resize(7000);
  for (std::size_t i = 0; i < sent.left.size(); ++i) sent.left[i] = static_cast<std::uint8_t>(i * 13 + 1);
  for (std::size_t i = 0; i < sent.right.size(); ++i) sent.right[i] = static_cast<std::uint8_t>(i * 7 + 3);
  sent.stereo.set_sequence(4);
  for (auto* image : {sent.stereo.mutable_left(), sent.stereo.mutable_right()}) {
    image->set_width(320);
    image->set_height(240);
    image->set_codec(proto::VIDEO_CODEC_H264);
    image->set_key_frame(false);
  }
  std::string error;
  for (const double fec : {0.0, 0.1}) {
    SCOPED_TRACE(fec > 0 ? "with parity" : "without parity");
    FramePacketizer packetizer(11, {kMaxChunkBytes, fec, 16, false});
    PacketizedFrame packets;
    ASSERT_TRUE(packetizer.packetize(sent.stereo, sent.left, sent.right, &packets, &error)) << error;
    EXPECT_TRUE(packets.predicted_codec);
    EXPECT_FALSE(packets.key_frame);
    {  // whole: byte-identical, the codec kept
      FrameAssembler assembler;
      std::vector<AssembledFrame> out;
      for (const auto& d : packets.datagrams) assembler.add(d, 0, out);
      ASSERT_EQ(out.size(), 1u);
      EXPECT_EQ(out[0].left_jpeg, sent.left);
      EXPECT_EQ(out[0].right_jpeg, sent.right);
      EXPECT_EQ(out[0].stereo.left().codec(), proto::VIDEO_CODEC_H264);
      EXPECT_TRUE(out[0].left_lost.empty());
    }
    {  // one chunk of the left image lost: rebuilt by parity, or the frame is not delivered
      FrameAssembler assembler;
      std::vector<AssembledFrame> out;
      for (std::size_t i = 0; i < packets.datagrams.size(); ++i)
        if (i != packets.chunk_datagram[2]) assembler.add(packets.datagrams[i], 0, out);
      assembler.expire(100 * kMs, out);
      if (fec > 0) {
        ASSERT_EQ(out.size(), 1u);
        EXPECT_EQ(out[0].left_jpeg, sent.left);
        EXPECT_EQ(assembler.stats().chunks_recovered, 1u);
      } else {
        EXPECT_TRUE(out.empty()) << "a predicted frame with a hole was delivered";
        EXPECT_EQ(assembler.stats().frames_lost, 1u);
        EXPECT_EQ(assembler.stats().video_frames_lost, 1u);
        EXPECT_EQ(assembler.stats().frames_concealed, 0u);
      }
    }
  }
  // A key frame is named as one; a JPEG frame is not predicted.
  for (auto* image : {sent.stereo.mutable_left(), sent.stereo.mutable_right()}) image->set_key_frame(true);
  FramePacketizer packetizer(12, {});
  PacketizedFrame packets;
  ASSERT_TRUE(packetizer.packetize(sent.stereo, sent.left, sent.right, &packets, &error)) << error;
  EXPECT_TRUE(packets.key_frame);
  FramePacketizer jpeg_packetizer(13, {});
  const SentFrame jpeg = sendFrame(jpeg_packetizer, 64, 48, 1, 1);
  EXPECT_FALSE(jpeg.packets.predicted_codec);
  // The same bytes named MJPEG are refused: not a JPEG.
  sent.stereo.mutable_left()->set_codec(proto::VIDEO_CODEC_MJPEG);
  sent.stereo.mutable_right()->set_codec(proto::VIDEO_CODEC_MJPEG);
  EXPECT_FALSE(packetizer.packetize(sent.stereo, sent.left, sent.right, &packets, &error));
}

TEST(FrameAssembler, LatestWinsAndAnOvertakenFrameIsNeverRepaired) {
  FramePacketizer packetizer(11, {kMaxChunkBytes, 0.0, 16, false});
  const SentFrame f0 = sendFrame(packetizer, 320, 240, 4, 0);
  const SentFrame f1 = sendFrame(packetizer, 320, 240, 5, 1);
  FrameAssembler assembler;
  std::vector<AssembledFrame> out;
  // Half of frame 0, all of frame 1, then the rest of frame 0.
  const std::size_t half = f0.packets.datagrams.size() / 2;
  for (std::size_t i = 0; i < half; ++i) assembler.add(f0.packets.datagrams[i], 0, out);
  for (const auto& d : f1.packets.datagrams) assembler.add(d, 1 * kMs, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].frame, f1.packets.frame);
  EXPECT_EQ(assembler.stats().frames_superseded, 1u);
  for (std::size_t i = half; i < f0.packets.datagrams.size(); ++i) assembler.add(f0.packets.datagrams[i], 2 * kMs, out);
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(assembler.stats().dropped(MediaDropReason::kLate), f0.packets.datagrams.size() - half);
  EXPECT_EQ(assembler.framesPending(), 0u);
}

TEST(FrameAssembler, ARestartedSenderIsTakenOverAfterTheOldStreamFallsSilent) {
  FramePacketizer old_sender(21, {kMaxChunkBytes, 0.0, 16, false}), new_sender(22, {kMaxChunkBytes, 0.0, 16, false});
  const SentFrame a = sendFrame(old_sender, 160, 120, 6, 0);
  const SentFrame b = sendFrame(new_sender, 160, 120, 7, 0);
  FrameAssembler assembler;
  std::vector<AssembledFrame> out;
  for (const auto& d : a.packets.datagrams) assembler.add(d, 0, out);
  for (const auto& d : b.packets.datagrams) assembler.add(d, 100 * kMs, out);  // both alive: ignored
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(assembler.stats().dropped(MediaDropReason::kOtherStream), b.packets.datagrams.size());
  for (const auto& d : b.packets.datagrams) assembler.add(d, 700 * kMs, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].stream, 22u);
  EXPECT_EQ(out[1].frame, 0u) << "frame numbers start again with the new stream";
  EXPECT_EQ(assembler.stats().stream_changes, 1u);
}

TEST(FrameAssembler, ForgedAndInconsistentChunksAreCountedAndMemoryStaysBounded) {
  FrameAssembler::Config config;
  config.max_bytes_pending = 8u << 20;
  FrameAssembler assembler(config);
  std::vector<AssembledFrame> out;
  // Chunk 0 of 100 different frames, each claiming 3 MiB: never more than 8 MiB held.
  for (std::uint32_t frame = 0; frame < 100; ++frame) {
    MediaPacketHeader h;
    h.stream = 5;
    h.frame = frame;
    h.frame_bytes = 3u << 20;
    h.chunk_bytes = kMaxChunkBytes;
    h.meta_bytes = 10;
    std::vector<std::uint8_t> d;
    writeMediaPacket(h, std::vector<std::uint8_t>(kMaxChunkBytes, 0xAB), d);
    assembler.add(d, frame * kMs, out);
    ASSERT_LE(assembler.framesPending(), 2u);
  }
  EXPECT_TRUE(out.empty());
  // Chunk 0 held garbage where the meta belongs: the given-up frames are malformed, not lost.
  EXPECT_EQ(assembler.stats().frames_malformed + assembler.stats().frames_superseded, 98u);
  // A chunk of a pending frame that disagrees with its frame's size.
  MediaPacketHeader h;
  h.stream = 5;
  h.frame = 99;
  h.frame_bytes = 2u << 20;
  h.chunk_bytes = kMaxChunkBytes;
  h.meta_bytes = 10;
  h.chunk_index = 1;
  std::vector<std::uint8_t> d;
  writeMediaPacket(h, std::vector<std::uint8_t>(kMaxChunkBytes), d);
  assembler.add(d, 200 * kMs, out);
  EXPECT_EQ(assembler.stats().dropped(MediaDropReason::kInconsistent), 1u);
  // A frame beyond what may be pending is refused before anything is allocated.
  h.frame = 200;
  h.frame_bytes = 9u << 20;
  d.clear();
  writeMediaPacket(h, std::vector<std::uint8_t>(kMaxChunkBytes), d);
  assembler.add(d, 201 * kMs, out);
  EXPECT_EQ(assembler.stats().dropped(MediaDropReason::kTooLarge), 1u);
}

TEST(FrameAssembler, ParityRebuildsUpToItsShardsPerBlockAndNoMore) {
  // 10 % parity in blocks of 16: r = 2 per full block. Two chunks lost in a block: rebuilt, the
  // frame whole and byte-identical; three lost in one block: that block's bands filled.
  FramePacketizer packetizer(41, {});
  const SentFrame sent = sendFrame(packetizer, 640, 480, 8, 1);
  std::size_t parity = 0;
  for (const auto& d : sent.packets.datagrams) parity += d[3] == static_cast<std::uint8_t>(MediaPacketKind::kFrameParity);
  const std::size_t chunks = withoutRepeats(sent.packets).size();
  EXPECT_EQ(parity, 2 * (chunks / 16) + (chunks % 16 ? (chunks % 16 > 10 ? 2 : 1) : 0));
  const auto chunkIndex = [](const std::vector<std::uint8_t>& d) { return static_cast<int>(d[26] << 8 | d[27]); };
  const auto isChunk = [](const std::vector<std::uint8_t>& d) { return d[3] == static_cast<std::uint8_t>(MediaPacketKind::kFrameChunk); };
  for (int lost_in_block : {2, 3}) {
    SCOPED_TRACE(std::to_string(lost_in_block) + " chunks lost in block 2");
    FrameAssembler assembler;
    std::vector<AssembledFrame> out;
    for (const auto& d : sent.packets.datagrams) {
      const int c = chunkIndex(d);
      if (isChunk(d) && c >= 32 && c < 32 + lost_in_block) continue;  // block 2 starts at chunk 32
      if (isChunk(d) && c == 5) continue;                                 // and one in block 0
      assembler.add(d, 0, out);
    }
    assembler.expire(1'000'000'000, out);
    ASSERT_EQ(out.size(), 1u);
    if (lost_in_block == 2) {
      EXPECT_TRUE(out[0].whole());
      EXPECT_EQ(out[0].left_jpeg, sent.left);
      EXPECT_EQ(out[0].right_jpeg, sent.right);
      EXPECT_EQ(assembler.stats().chunks_recovered, 3u);
    } else {
      EXPECT_FALSE(out[0].whole());
      EXPECT_EQ(out[0].chunks_missing, 3u) << "block 0 rebuilt, block 2's three stay lost";
      EXPECT_EQ(assembler.stats().chunks_recovered, 1u);
      EXPECT_TRUE(test::decodePlanes(out[0].left_jpeg).ok);
    }
    EXPECT_GT(assembler.stats().parity_received, 0u);
    EXPECT_LE(assembler.stats().parity_received, parity) << "shards after the frame was whole come late";
  }
  // A forged parity shard for a block that overlaps a known one is refused.
  FrameAssembler assembler;
  std::vector<AssembledFrame> out;
  for (const auto& d : sent.packets.datagrams)
    if (!isChunk(d) && chunkIndex(d) == 0) assembler.add(d, 0, out);
  auto forged = sent.packets.datagrams.front();
  for (const auto& d : sent.packets.datagrams)
    if (!isChunk(d) && chunkIndex(d) == 16) forged = d;
  forged[27] = 8;  // block "8..23" overlaps block 0..15
  assembler.add(forged, 0, out);
  EXPECT_EQ(assembler.stats().dropped(MediaDropReason::kInconsistent), 1u);
}

/// The chunk index a frame datagram carries, and whether it is a chunk (not parity).
int chunkOf(const std::vector<std::uint8_t>& d) { return static_cast<int>(d[26] << 8 | d[27]); }
bool isChunkDatagram(const std::vector<std::uint8_t>& d) {
  return d[3] == static_cast<std::uint8_t>(MediaPacketKind::kFrameChunk);
}

TEST(FrameAssembler, AsksOnlyForWhatParityCannotRebuildAndTheRepairMakesTheFrameWhole) {
  FramePacketizer packetizer(43, {});
  const SentFrame sent = sendFrame(packetizer, 640, 480, 8, 1);
  FrameAssembler::Config config;
  config.repair = true;
  FrameAssembler assembler(config);
  std::vector<AssembledFrame> out;
  // Three chunks of block 2 (chunks 32..47, two parity shards) lost: one must come again.
  std::int64_t t = 0;
  bool asked_early = false;
  for (const auto& d : sent.packets.datagrams) {
    const int c = chunkOf(d);
    t += 100'000;  // 0.1 ms apart
    if (isChunkDatagram(d) && c >= 32 && c < 35) continue;
    assembler.add(d, t, out);
    // Before the block's parity and the next block, nothing is asked for.
    if (isChunkDatagram(d) && c < 40) asked_early |= assembler.takeRepairRequest(t).has_value();
    else if (isChunkDatagram(d) && c == 48) break;  // the next block began: block 2 is closed
  }
  EXPECT_FALSE(asked_early);
  const auto request = assembler.takeRepairRequest(t);
  ASSERT_TRUE(request);
  EXPECT_EQ(request->frame, sent.packets.frame);
  EXPECT_EQ(request->chunks, std::vector<std::uint16_t>{32}) << "3 lost, 2 parity shards: one chunk more";
  EXPECT_FALSE(assembler.takeRepairRequest(t + 1'000'000)) << "asked once, not again before its wait";
  // The rest of the frame and the repaired chunk, 40 ms after the request.
  bool past = false;
  for (const auto& d : sent.packets.datagrams) {
    if (isChunkDatagram(d) && chunkOf(d) == 48) past = true;
    if (past) assembler.add(d, t + 1'000'000, out);
  }
  EXPECT_TRUE(out.empty()) << "block 2 still short";
  assembler.expire(t + 35'000'000, out);
  EXPECT_TRUE(out.empty()) << "waiting for its repair beyond the 30 ms grace";
  for (const auto& d : sent.packets.datagrams)
    if (isChunkDatagram(d) && chunkOf(d) == 32) assembler.add(d, t + 40'000'000, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].whole());
  EXPECT_EQ(out[0].left_jpeg, sent.left);
  EXPECT_EQ(out[0].right_jpeg, sent.right);
  EXPECT_EQ(assembler.stats().chunks_requested, 1u);
  EXPECT_EQ(assembler.stats().chunks_repaired, 1u);
  EXPECT_NEAR(assembler.stats().repair_rtt_ms, 40.0, 1e-9);
  EXPECT_EQ(assembler.repairWaitNs(), 65'000'000) << "1.5 × 40 ms + 5 ms";
}

TEST(FrameAssembler, WithoutParityAGapIsAskedForWhenALaterChunkArrivesTheTailWhenTheFrameIsQuiet) {
  FramePacketizer::Config no_fec;
  no_fec.fec_overhead = 0;
  no_fec.repeat_headers = false;
  FramePacketizer packetizer(44, no_fec);
  const SentFrame sent = sendFrame(packetizer, 640, 480, 9, 1);
  FrameAssembler::Config config;
  config.repair = true;
  config.repair_rtt_initial_ns = 20'000'000;  // wait 1.5 × 20 + 5 = 35 ms
  config.repair_attempts = 1;
  FrameAssembler assembler(config);
  std::vector<AssembledFrame> out;
  std::int64_t t = 0;
  const int last = chunkOf(sent.packets.datagrams.back());
  std::vector<std::uint16_t> asked;
  for (const auto& d : sent.packets.datagrams) {
    t += 100'000;
    if (chunkOf(d) == 7 || chunkOf(d) == last) continue;  // one inside, and the frame's last chunk
    assembler.add(d, t, out);
    if (const auto r = assembler.takeRepairRequest(t)) {
      EXPECT_EQ(chunkOf(d), 8) << "chunk 7 is known lost when chunk 8 arrives, and not before";
      asked.insert(asked.end(), r->chunks.begin(), r->chunks.end());
    }
  }
  EXPECT_EQ(asked, std::vector<std::uint16_t>{7});
  // The tail: nothing says it was sent until the frame has been quiet for 20 ms.
  EXPECT_FALSE(assembler.takeRepairRequest(t + 19'000'000));
  const auto tail = assembler.takeRepairRequest(t + 20'000'000);
  ASSERT_TRUE(tail);
  EXPECT_EQ(tail->chunks, std::vector<std::uint16_t>{static_cast<std::uint16_t>(last)});
  // The repairs never come: the frame waits 35 ms from the last request, then is shown concealed.
  assembler.expire(t + 54'000'000, out);
  EXPECT_TRUE(out.empty());
  EXPECT_FALSE(assembler.takeRepairRequest(t + 56'000'000)) << "one attempt per chunk here";
  assembler.expire(t + 56'000'000, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].whole());
  EXPECT_EQ(assembler.stats().chunks_requested, 2u);
  EXPECT_EQ(assembler.stats().chunks_repaired, 0u);
}

TEST(FrameAssembler, TheRepairWaitFollowsTheOtherLinksRoundTripUntilARepairMeasuresItsOwn) {
  FrameAssembler::Config config;
  config.repair = true;
  config.repair_wait_max_ns = 300'000'000;
  FrameAssembler assembler(config);
  EXPECT_EQ(assembler.repairWaitNs(), 155'000'000) << "100 ms assumed";
  assembler.setRoundTripHintNs(20'000'000);
  EXPECT_EQ(assembler.repairWaitNs(), 35'000'000);
  assembler.setRoundTripHintNs(-5);
  EXPECT_EQ(assembler.repairWaitNs(), 35'000'000) << "nonsense is ignored";
  assembler.setRoundTripHintNs(400'000'000);
  EXPECT_EQ(assembler.repairWaitNs(), 300'000'000) << "never beyond the maximum";
}

TEST(FrameAssembler, AFrameWaitingForRepairsIsSupersededByANewerWholeOne) {
  FramePacketizer packetizer(45, {});
  const SentFrame first = sendFrame(packetizer, 640, 480, 10, 1);
  const SentFrame second = sendFrame(packetizer, 640, 480, 11, 2);
  FrameAssembler::Config config;
  config.repair = true;
  FrameAssembler assembler(config);
  std::vector<AssembledFrame> out;
  for (const auto& d : first.packets.datagrams)
    if (!(isChunkDatagram(d) && chunkOf(d) >= 16 && chunkOf(d) < 19)) assembler.add(d, 0, out);
  ASSERT_TRUE(assembler.takeRepairRequest(6'000'000));
  for (const auto& d : second.packets.datagrams) assembler.add(d, 20'000'000, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].frame, second.packets.frame) << "latest wins: the first is never shown";
  EXPECT_EQ(assembler.stats().frames_superseded, 1u);
  EXPECT_FALSE(assembler.takeRepairRequest(60'000'000)) << "nothing pending, nothing to ask";
}

TEST(FrameAssembler, SeededRandomLossAndReorderingNeverYieldAnInvalidJpeg) {
  FramePacketizer packetizer(31, {});
  FrameAssembler assembler;
  std::mt19937 rng(2026);
  std::bernoulli_distribution lose(0.03);
  std::vector<AssembledFrame> out;
  std::vector<SentFrame> sent;
  std::int64_t now = 0;
  for (int frame = 0; frame < 12; ++frame) {
    sent.push_back(sendFrame(packetizer, 480, 320, 10 + frame, static_cast<std::uint64_t>(frame)));
    auto datagrams = sent.back().packets.datagrams;
    // Local reordering: swap neighbours now and then.
    for (std::size_t i = 1; i < datagrams.size(); ++i)
      if (rng() % 5 == 0) std::swap(datagrams[i - 1], datagrams[i]);
    for (const auto& d : datagrams) {
      now += 100'000;
      if (!lose(rng)) assembler.add(d, now, out);
    }
    now += 40 * kMs;  // the next frame comes a frame period later
    assembler.expire(now, out);
  }
  ASSERT_GE(out.size(), 8u);
  std::size_t concealed = 0;
  for (const AssembledFrame& f : out) {
    const SentFrame& s = sent[f.frame];
    for (int eye = 0; eye < 2; ++eye) {
      const auto& jpeg = eye == 0 ? f.left_jpeg : f.right_jpeg;
      const auto& lost = eye == 0 ? f.left_lost : f.right_lost;
      const test::Planes got = test::decodePlanes(jpeg), original = test::decodePlanes(eye == 0 ? s.left : s.right);
      ASSERT_TRUE(got.ok) << "frame " << f.frame << " eye " << eye;
      for (int y = 0; y < 320; ++y) {
        const bool in_lost = std::any_of(lost.begin(), lost.end(), [&](const LostRows& r) { return y >= r.first && y < r.end; });
        if (!in_lost) {
          ASSERT_TRUE(std::equal(got.y.begin() + y * 480, got.y.begin() + (y + 1) * 480, original.y.begin() + y * 480))
              << "frame " << f.frame << " eye " << eye << " row " << y;
        }
      }
    }
    if (!f.whole()) ++concealed;
  }
  const auto& st = assembler.stats();
  EXPECT_EQ(st.frames_whole + st.frames_concealed, out.size());
  EXPECT_EQ(st.frames_whole + st.frames_concealed + st.frames_lost + st.frames_superseded + st.frames_malformed, 12u);
  EXPECT_EQ(st.frames_malformed, 0u);
  EXPECT_GT(concealed + st.chunks_recovered, 0u) << "3 % loss over ~100 chunks a frame: rebuilt or concealed";
}

}  // namespace
}  // namespace telesphere::link::media
