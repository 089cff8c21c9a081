// SPDX-License-Identifier: MIT
/// @brief telesphere-mcap: looks into session recordings (robot/record).
///
///   telesphere-mcap summary FILE [--json] [--scan]   channels, counts, duration, rates
///   telesphere-mcap check FILE                        every message read, every CRC checked
///   telesphere-mcap recover IN OUT [--compression C]  the intact part of a cut-off file, finished
///
/// Exit codes: 0 ok, 1 bad arguments, 2 the file is damaged or cannot be read/written.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "robot/record/mcap_reader.h"
#include "robot/record/mcap_recover.h"

namespace record = telesphere::record;

namespace {

int summary(const std::string& path, bool json, bool scan) {
  std::string error;
  const auto reader = record::McapReader::open(path, &error);
  record::McapSummary s;
  if (!reader || !reader->summary(&s, &error, scan)) {
    std::cerr << "telesphere-mcap: " << path << ": " << error << '\n';
    return 2;
  }
  const double duration_s = s.messages > 1 ? double(s.end_ns - s.start_ns) * 1e-9 : 0.0;
  if (json) {
    nlohmann::json j;
    j["file"] = path;
    j["bytes"] = reader->fileSize();
    j["library"] = s.library;
    j["messages"] = s.messages;
    j["chunks"] = s.chunks;
    j["attachments"] = s.attachments;
    j["metadata"] = s.metadata;
    j["start_ns"] = s.start_ns;
    j["end_ns"] = s.end_ns;
    j["duration_s"] = duration_s;
    j["from_summary_section"] = s.from_summary_section;
    if (!s.summary_problem.empty()) j["summary_problem"] = s.summary_problem;
    j["compression"] = nlohmann::json::array();
    for (const auto& c : s.compressions) j["compression"].push_back(c.empty() ? "none" : c);
    for (const auto& [id, c] : s.channels) {
      const std::uint64_t n = s.channel_messages.count(id) ? s.channel_messages.at(id) : 0;
      const auto schema = s.schemas.find(c.schema_id);
      j["channels"][c.topic] = {{"id", id},
                                {"schema", schema != s.schemas.end() ? schema->second.name : ""},
                                {"schema_encoding", schema != s.schemas.end() ? schema->second.encoding : ""},
                                {"message_encoding", c.message_encoding},
                                {"messages", n},
                                {"rate_hz", duration_s > 0 ? double(n) / duration_s : 0.0}};
    }
    std::cout << j.dump(2) << '\n';
    return 0;
  }
  std::printf("%s: %.1f MB, %llu messages in %llu chunks over %.2f s (written by %s; %s)\n", path.c_str(),
              double(reader->fileSize()) * 1e-6, static_cast<unsigned long long>(s.messages),
              static_cast<unsigned long long>(s.chunks), duration_s, s.library.empty() ? "?" : s.library.c_str(),
              s.from_summary_section ? "from its summary"
              : s.summary_problem.empty() ? "counted by reading it: no summary section"
                                          : ("counted by reading it: " + s.summary_problem).c_str());
  std::string compressions;
  for (const auto& c : s.compressions) compressions += (compressions.empty() ? "" : ", ") + (c.empty() ? "none" : c);
  std::printf("chunk compression: %s\n", compressions.empty() ? "-" : compressions.c_str());
  std::printf("attachments: %llu, metadata records: %llu\n\n", static_cast<unsigned long long>(s.attachments),
              static_cast<unsigned long long>(s.metadata));
  std::printf("%-26s %-40s %10s %10s\n", "topic", "schema", "messages", "rate Hz");
  for (const auto& [id, c] : s.channels) {
    const std::uint64_t n = s.channel_messages.count(id) ? s.channel_messages.at(id) : 0;
    const auto schema = s.schemas.find(c.schema_id);
    std::printf("%-26s %-40s %10llu %10.2f\n", c.topic.c_str(),
                schema != s.schemas.end() ? schema->second.name.c_str() : "-", static_cast<unsigned long long>(n),
                duration_s > 0 ? double(n) / duration_s : 0.0);
  }
  return 0;
}

int check(const std::string& path) {
  std::string error;
  const auto reader = record::McapReader::open(path, &error);
  if (!reader) {
    std::cerr << "telesphere-mcap: " << error << '\n';
    return 2;
  }
  std::uint64_t messages = 0, bytes = 0, attachments = 0, metadata = 0;
  record::McapReader::Extras extras;
  extras.on_attachment = [&](const record::McapAttachmentView&) { return ++attachments, true; };
  extras.on_metadata = [&](const record::McapMetadata&) { return ++metadata, true; };
  if (!reader->forEachRecord(
          [&](const record::McapMessageView& m) {
            ++messages;
            bytes += m.size;
            return true;
          },
          extras, &error)) {
    std::cerr << "telesphere-mcap: " << path << ": " << error << " (after " << messages
              << " intact messages; `telesphere-mcap recover` keeps them)\n";
    return 2;
  }
  // The summary section carries a CRC of its own: a file whose summary is damaged reads, but a
  // tool that trusts the summary (Foxglove's, MCAP's) would be misled, so check says so.
  record::McapSummary summary;
  if (!reader->summary(&summary, &error)) {
    std::cerr << "telesphere-mcap: " << path << ": " << error << '\n';
    return 2;
  }
  if (!summary.summary_problem.empty()) {
    std::cerr << "telesphere-mcap: " << path << ": the summary section is damaged (" << summary.summary_problem
              << "): the messages read, `telesphere-mcap recover` writes a whole file\n";
    return 2;
  }
  if (summary.from_summary_section &&
      (summary.messages != messages || summary.attachments != attachments || summary.metadata != metadata)) {
    std::cerr << "telesphere-mcap: " << path << ": the summary counts " << summary.messages << " messages, "
              << summary.attachments << " attachments, " << summary.metadata << " metadata; the file holds " << messages
              << ", " << attachments << ", " << metadata << '\n';
    return 2;
  }
  std::printf("%s: %llu messages, %.1f MB of payload, %llu attachments, %llu metadata; every CRC the file carries "
              "holds (chunks, attachments, data section%s)\n",
              path.c_str(), static_cast<unsigned long long>(messages), double(bytes) * 1e-6,
              static_cast<unsigned long long>(attachments), static_cast<unsigned long long>(metadata),
              summary.from_summary_section ? ", summary" : "; no summary section");
  return 0;
}

int recover(const std::string& in, const std::string& out, const std::string& compression) {
  record::McapWriterOptions options;
  options.compression = *record::parseCompression(compression);
  record::McapRecoverReport report;
  std::string error;
  if (!record::recoverMcap(in, out, options, &report, &error)) {
    std::cerr << "telesphere-mcap: " << error << '\n';
    return 2;
  }
  if (report.damage.empty())
    std::printf("%s was whole: %llu messages copied to %s\n", in.c_str(),
                static_cast<unsigned long long>(report.messages), out.c_str());
  else
    std::printf("%s: %llu messages kept (%.1f of %.1f MB intact; then %s at byte %llu); written to %s\n", in.c_str(),
                static_cast<unsigned long long>(report.messages), double(report.intact_bytes) * 1e-6,
                double(report.file_bytes) * 1e-6, report.damage.c_str(),
                static_cast<unsigned long long>(report.intact_bytes), out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"telesphere-mcap: session recordings (MCAP) — summary, check, recover"};
  app.require_subcommand(1);
  std::string file, out, compression = "none";
  bool json = false, scan = false;
  auto* s = app.add_subcommand("summary", "channels, message counts, duration and rates of a recording");
  s->add_option("file", file, "the MCAP file")->required();
  s->add_flag("--json", json, "as JSON");
  s->add_flag("--scan", scan, "count by reading every message instead of trusting the summary section");
  auto* c = app.add_subcommand("check", "read every message, checking every CRC");
  c->add_option("file", file, "the MCAP file")->required();
  auto* r = app.add_subcommand("recover", "write the intact part of a cut-off recording as a complete file");
  r->add_option("in", file, "the damaged MCAP file")->required();
  r->add_option("out", out, "the file to write")->required();
  r->add_option("--compression", compression, "chunk compression of the new file (none, lz4, zstd)")
      ->capture_default_str()->check(CLI::IsMember({"none", "lz4", "zstd"}));
  CLI11_PARSE(app, argc, argv);
  if (s->parsed()) return summary(file, json, scan);
  if (c->parsed()) return check(file);
  return recover(file, out, compression);
}
