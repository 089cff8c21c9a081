// SPDX-License-Identifier: MIT
/// @brief Our MCAP writer against our reader: seeded random messages round-trip in order through
///        every compression and many chunks; the summary section agrees with a full read; a file
///        cut at every point reads up to its last whole chunk and recovers to a complete file
///        holding exactly those messages; flipped bytes, absurd lengths and non-MCAP input give
///        reasons, never a crash. (Files read by an implementation no one here wrote:
///        tests/interop/mcap.)
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>

#include "robot/record/mcap_reader.h"
#include "robot/record/mcap_recover.h"
#include "robot/record/mcap_writer.h"

namespace telesphere::record {
namespace {

struct Msg {
  std::uint16_t channel;
  std::uint32_t sequence;
  std::uint64_t log_ns, publish_ns;
  std::string data;
  bool operator==(const Msg& o) const {
    return channel == o.channel && sequence == o.sequence && log_ns == o.log_ns && publish_ns == o.publish_ns &&
           data == o.data;
  }
};

std::filesystem::path tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("telesphere-mcap-" + std::to_string(getpid()) + "-" + name);
}

std::vector<Msg> randomMessages(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Msg> out;
  std::uint64_t t = 1'000'000'000;
  for (std::size_t i = 0; i < n; ++i) {
    Msg m;
    m.channel = static_cast<std::uint16_t>(rng() % 3);
    m.sequence = static_cast<std::uint32_t>(i);
    t += rng() % 5'000'000;
    m.log_ns = t;
    m.publish_ns = t - rng() % 1000;
    // Sizes from empty to 20 kB, some compressible, some not.
    m.data.resize(rng() % 3 == 0 ? rng() % 20000 : rng() % 200);
    for (char& c : m.data) c = static_cast<char>(i % 2 == 0 ? rng() : 'a' + (rng() % 3));
    out.push_back(std::move(m));
  }
  return out;
}

/// Writes `messages` on three channels (two sharing a schema) with small chunks.
bool writeFile(const std::string& path, const std::vector<Msg>& messages, McapCompression compression,
               std::size_t chunk_size = 16 * 1024) {
  McapWriterOptions options;
  options.compression = compression;
  options.chunk_size = chunk_size;
  std::string error;
  auto w = McapWriter::create(path, options, &error);
  if (!w) return false;
  const std::uint16_t s1 = w->addSchema("pkg.A", "protobuf", std::string("\x0a\x01x", 3));
  const std::uint16_t s2 = w->addSchema("pkg.B", "protobuf", "");
  EXPECT_EQ(s1, 1);
  EXPECT_EQ(s2, 2);
  EXPECT_EQ(w->addChannel("/a", s1, "protobuf", {{"k", "v"}}), 0);
  EXPECT_EQ(w->addChannel("/b", s1, "protobuf"), 1);
  EXPECT_EQ(w->addChannel("/c", s2, "protobuf"), 2);
  for (const Msg& m : messages)
    if (!w->write(m.channel, m.sequence, m.log_ns, m.publish_ns, m.data.data(), m.data.size())) return false;
  return w->close();
}

std::vector<Msg> readAll(const McapReader& r, std::string* error, bool stop_at_damage = false,
                         McapDamage* damage = nullptr, bool* ok = nullptr) {
  std::vector<Msg> out;
  const bool read = r.forEachMessage(
      [&](const McapMessageView& m) {
        out.push_back({m.channel->id, m.sequence, m.log_time_ns, m.publish_time_ns,
                       std::string(reinterpret_cast<const char*>(m.data), m.size)});
        return true;
      },
      error, stop_at_damage, damage);
  if (ok != nullptr) *ok = read;
  return out;
}

std::vector<std::uint8_t> fileBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

class McapRoundTrip : public ::testing::TestWithParam<McapCompression> {};

TEST_P(McapRoundTrip, EveryMessageComesBackInOrderAndTheSummaryAgrees) {
  const auto messages = randomMessages(1500, 7);
  const std::string path = tempFile("roundtrip.mcap").string();
  ASSERT_TRUE(writeFile(path, messages, GetParam()));
  std::string error;
  const auto r = McapReader::open(path, &error);
  ASSERT_TRUE(r) << error;
  bool ok = false;
  EXPECT_EQ(readAll(*r, &error, false, nullptr, &ok), messages);
  EXPECT_TRUE(ok) << error;
  McapSummary from_section, scanned;
  ASSERT_TRUE(r->summary(&from_section, &error)) << error;
  ASSERT_TRUE(r->summary(&scanned, &error, true)) << error;
  EXPECT_TRUE(from_section.from_summary_section);
  EXPECT_FALSE(scanned.from_summary_section);
  for (const McapSummary* s : {&from_section, &scanned}) {
    EXPECT_EQ(s->messages, messages.size());
    EXPECT_GT(s->chunks, 20u);
    EXPECT_EQ(s->start_ns, messages.front().log_ns);
    EXPECT_EQ(s->end_ns, messages.back().log_ns);
    EXPECT_EQ(s->library, "telesphere");
    ASSERT_EQ(s->channels.size(), 3u);
    EXPECT_EQ(s->channels.at(0).topic, "/a");
    EXPECT_EQ(s->channels.at(0).metadata.at("k"), "v");
    EXPECT_EQ(s->schemas.at(1).name, "pkg.A");
    EXPECT_EQ(s->schemas.at(1).data, std::string("\x0a\x01x", 3));
    EXPECT_EQ(s->compressions, std::set<std::string>{std::string(compressionName(GetParam()))});
  }
  std::uint64_t total = 0;
  for (const auto& [channel, n] : from_section.channel_messages) {
    EXPECT_EQ(n, scanned.channel_messages.at(channel));
    total += n;
  }
  EXPECT_EQ(total, messages.size());
  std::filesystem::remove(path);
}

INSTANTIATE_TEST_SUITE_P(Compressions, McapRoundTrip,
                         ::testing::Values(McapCompression::kNone, McapCompression::kLz4, McapCompression::kZstd),
                         [](const auto& info) {
                           return info.param == McapCompression::kNone ? std::string("none")
                                                                       : std::string(compressionName(info.param));
                         });

TEST(Mcap, AFileWithoutMessagesIsValid) {
  const std::string path = tempFile("empty.mcap").string();
  ASSERT_TRUE(writeFile(path, {}, McapCompression::kZstd));
  std::string error;
  const auto r = McapReader::open(path, &error);
  ASSERT_TRUE(r) << error;
  McapSummary s;
  ASSERT_TRUE(r->summary(&s, &error)) << error;
  EXPECT_EQ(s.messages, 0u);
  EXPECT_EQ(s.chunks, 0u);
  EXPECT_EQ(s.channels.size(), 3u);
  std::filesystem::remove(path);
}

// Metadata and attachments (issue #30): in their place in the data section, indexed and counted
// in the summary, an attachment's CRC checked (a flipped byte in it is damage), kept by recover.
TEST(Mcap, MetadataAndAttachmentsRoundTripAreIndexedCheckedAndRecovered) {
  const std::string path = tempFile("attached.mcap").string();
  std::string error;
  {
    auto w = McapWriter::create(path, {}, &error);
    ASSERT_TRUE(w) << error;
    const auto schema = w->addSchema("s", "protobuf", "x");
    const auto channel = w->addChannel("/a", schema, "protobuf");
    ASSERT_TRUE(w->writeMetadata("telesphere", {{"steady_to_utc_offset_ns", "42"}, {"arm", "xArm 6"}}));
    const std::string yaml = "cameras: []\n";
    ASSERT_TRUE(w->writeAttachment(100, 100, "calibration-generation-1.yaml", "application/yaml", yaml.data(), yaml.size()));
    for (std::uint32_t i = 0; i < 10; ++i) ASSERT_TRUE(w->write(channel, i, 200 + i, 200 + i, "m", 1));
    ASSERT_TRUE(w->writeAttachment(300, 301, "calibration-generation-2.yaml", "application/yaml", yaml.data(), yaml.size()));
    ASSERT_TRUE(w->write(channel, 10, 400, 400, "m", 1));
    ASSERT_TRUE(w->close());
  }
  const auto read = [&](const std::string& file, std::vector<std::string>* names, std::vector<McapMetadata>* meta,
                        std::uint64_t* messages) {
    const auto r = McapReader::open(file, &error);
    EXPECT_TRUE(r) << error;
    if (!r) return false;
    McapReader::Extras extras;
    extras.on_attachment = [&](const McapAttachmentView& a) {
      names->push_back(a.name + "@" + std::to_string(a.log_time_ns) + ":" + std::string(reinterpret_cast<const char*>(a.data), a.size));
      return true;
    };
    extras.on_metadata = [&](const McapMetadata& m) {
      meta->push_back(m);
      return true;
    };
    return r->forEachRecord([&](const McapMessageView&) { return ++*messages, true; }, extras, &error);
  };
  std::vector<std::string> names;
  std::vector<McapMetadata> meta;
  std::uint64_t messages = 0;
  ASSERT_TRUE(read(path, &names, &meta, &messages)) << error;
  EXPECT_EQ(messages, 11u);
  EXPECT_EQ(names, (std::vector<std::string>{"calibration-generation-1.yaml@100:cameras: []\n",
                                             "calibration-generation-2.yaml@300:cameras: []\n"}));
  ASSERT_EQ(meta.size(), 1u);
  EXPECT_EQ(meta[0].name, "telesphere");
  EXPECT_EQ(meta[0].metadata.at("steady_to_utc_offset_ns"), "42");
  {
    const auto r = McapReader::open(path, &error);
    McapSummary s;
    ASSERT_TRUE(r->summary(&s, &error)) << error;
    EXPECT_TRUE(s.from_summary_section);
    EXPECT_EQ(s.attachments, 2u);
    EXPECT_EQ(s.metadata, 1u);
    McapSummary scanned;
    ASSERT_TRUE(r->summary(&scanned, &error, true)) << error;
    EXPECT_EQ(scanned.attachments, 2u);
    EXPECT_EQ(scanned.metadata, 1u);
  }
  // A flipped byte inside the first attachment's data: its CRC says so.
  auto bytes = fileBytes(path);
  const std::string needle = "cameras: []";
  const auto at = std::search(bytes.begin(), bytes.end(), needle.begin(), needle.end());
  ASSERT_NE(at, bytes.end());
  *at ^= 0x01;
  {
    const auto r = McapReader::fromBytes(bytes.data(), bytes.size(), &error);
    ASSERT_TRUE(r) << error;
    std::string why;
    EXPECT_FALSE(r->forEachRecord([](const McapMessageView&) { return true; }, {}, &why));
    EXPECT_NE(why.find("attachment CRC mismatch"), std::string::npos) << why;
  }
  // recover keeps them.
  const std::string fixed = tempFile("attached-fixed.mcap").string();
  McapRecoverReport report;
  ASSERT_TRUE(recoverMcap(path, fixed, {}, &report, &error)) << error;
  std::vector<std::string> fixed_names;
  std::vector<McapMetadata> fixed_meta;
  messages = 0;
  ASSERT_TRUE(read(fixed, &fixed_names, &fixed_meta, &messages)) << error;
  EXPECT_EQ(fixed_names, names);
  ASSERT_EQ(fixed_meta.size(), 1u);
  EXPECT_EQ(fixed_meta[0].metadata, meta[0].metadata);
  EXPECT_EQ(messages, 11u);
  std::filesystem::remove(path);
  std::filesystem::remove(fixed);
}

TEST(Mcap, ACutFileReadsToItsLastWholeChunkAndRecoversExactlyThat) {
  for (const McapCompression compression : {McapCompression::kNone, McapCompression::kZstd}) {
    const auto messages = randomMessages(300, 11);
    const std::string path = tempFile("whole.mcap").string();
    ASSERT_TRUE(writeFile(path, messages, compression, 8 * 1024));
    const auto bytes = fileBytes(path);
    std::size_t recovered_files = 0, previous = 0, cuts_after_the_data = 0;
    // Every cut: 97 places across the file, plus just before and after its end.
    for (std::size_t cut = 9; cut < bytes.size(); cut += bytes.size() / 97 + 1) {
      std::string error;
      const auto r = McapReader::fromBytes(bytes.data(), cut, &error);
      ASSERT_TRUE(r) << error;
      bool ok = true;
      const auto strict = readAll(*r, &error, false, nullptr, &ok);
      // A cut in the summary leaves the data section whole: every message reads.
      const bool data_whole = ok;
      if (data_whole) {
        EXPECT_EQ(strict, messages) << "cut at " << cut;
        ++cuts_after_the_data;
      } else {
        EXPECT_NE(error.find("at byte"), std::string::npos) << error;
      }
      McapDamage damage;
      const auto kept = readAll(*r, &error, true, &damage, &ok);
      EXPECT_TRUE(ok);
      EXPECT_LE(damage.offset, cut);
      EXPECT_EQ(damage.reason.empty(), data_whole) << damage.reason;
      // What is kept is a prefix of what was written, and never shrinks as the cut moves on.
      ASSERT_LE(kept.size(), messages.size());
      EXPECT_TRUE(std::equal(kept.begin(), kept.end(), messages.begin())) << "cut at " << cut;
      EXPECT_GE(kept.size(), previous);
      previous = kept.size();
      // recover writes exactly those messages into a complete file.
      const std::string cut_path = tempFile("cut.mcap").string(), fixed_path = tempFile("fixed.mcap").string();
      {
        std::ofstream f(cut_path, std::ios::binary);
        f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(cut));
      }
      McapRecoverReport report;
      ASSERT_TRUE(recoverMcap(cut_path, fixed_path, {}, &report, &error)) << error;
      EXPECT_EQ(report.messages, kept.size());
      EXPECT_EQ(report.intact_bytes, data_whole ? cut : damage.offset);
      const auto fixed = McapReader::open(fixed_path, &error);
      ASSERT_TRUE(fixed) << error;
      EXPECT_EQ(readAll(*fixed, &error, false, nullptr, &ok), kept);
      EXPECT_TRUE(ok) << error;
      McapSummary s;
      EXPECT_TRUE(fixed->summary(&s, &error)) << error;
      EXPECT_TRUE(s.from_summary_section);
      ++recovered_files;
      std::filesystem::remove(cut_path);
      std::filesystem::remove(fixed_path);
    }
    EXPECT_GT(recovered_files, 90u);
    EXPECT_LT(cuts_after_the_data, 5u);  // the summary is a small part of the file
    EXPECT_GT(previous, 250u);  // the last cuts keep nearly everything
    std::filesystem::remove(path);
  }
}

TEST(Mcap, FlippedBytesAndAbsurdLengthsGiveReasons) {
  const auto messages = randomMessages(200, 3);
  const std::string path = tempFile("flip.mcap").string();
  ASSERT_TRUE(writeFile(path, messages, McapCompression::kNone, 4 * 1024));
  const auto bytes = fileBytes(path);
  std::mt19937 rng(5);
  std::size_t detected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    auto damaged = bytes;
    const std::size_t at = 8 + rng() % (damaged.size() - 16);
    damaged[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
    std::string error;
    const auto r = McapReader::fromBytes(damaged.data(), damaged.size(), &error);
    ASSERT_TRUE(r);
    bool ok = true;
    const auto got = readAll(*r, &error, false, nullptr, &ok);
    McapSummary s;
    const bool summary_ok = r->summary(&s, &error) && s.summary_problem.empty();
    // Either the damage is found, or it sat where nothing is checked (an index, a time field of
    // a chunk) and every message still came back intact.
    if (!ok || !summary_ok || got != messages)
      ++detected;
    else
      EXPECT_EQ(got, messages);
    if (!ok) {
      EXPECT_FALSE(error.empty());
    }
  }
  EXPECT_GT(detected, 200u);
  // A record claiming 2^63 bytes.
  auto huge = bytes;
  const std::size_t first_record = 8;
  huge[first_record + 8] = 0x80;
  std::string error;
  const auto r = McapReader::fromBytes(huge.data(), huge.size(), &error);
  ASSERT_TRUE(r);
  bool ok = true;
  readAll(*r, &error, false, nullptr, &ok);
  EXPECT_FALSE(ok);
  EXPECT_NE(error.find("claims"), std::string::npos) << error;
  // Not MCAP at all.
  const std::string text = "hello, this is not a recording";
  EXPECT_FALSE(McapReader::fromBytes(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), &error));
  EXPECT_NE(error.find("not an MCAP file"), std::string::npos);
  EXPECT_FALSE(McapReader::open(tempFile("missing.mcap").string(), &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  std::filesystem::remove(path);
}

TEST(Mcap, RecoverNeverWritesOverAFileLeastOfAllItsInput) {
  const std::string path = tempFile("self.mcap").string();
  ASSERT_TRUE(writeFile(path, randomMessages(20, 1), McapCompression::kNone));
  const auto size = std::filesystem::file_size(path);
  McapRecoverReport report;
  std::string error;
  EXPECT_FALSE(recoverMcap(path, path, {}, &report, &error));  // would truncate what it maps
  EXPECT_NE(error.find("exists"), std::string::npos) << error;
  EXPECT_EQ(std::filesystem::file_size(path), size);
  std::filesystem::remove(path);
}

TEST(Mcap, AnUnwritableFileIsRefusedWithTheReason) {
  std::string error;
  EXPECT_FALSE(McapWriter::create("/nonexistent-dir/x.mcap", {}, &error));
  EXPECT_NE(error.find("cannot create /nonexistent-dir/x.mcap"), std::string::npos) << error;
}

}  // namespace
}  // namespace telesphere::record
