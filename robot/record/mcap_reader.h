// SPDX-License-Identifier: MIT
/// @brief Reads an MCAP file (mcap.dev/spec) from memory or a mapped file: its summary (from the
///        summary section when the footer points at one whose CRC holds, else by scanning), and
///        every message in file order, checking each chunk's CRC and the data section's.
///
/// Built for files that are damaged or cut off: every field is bounds-checked, a bad record
/// ends the read with the byte offset and the reason, never a crash (fuzzed:
/// fuzz_mcap_reader). With `stop_at_damage` a read stops cleanly at the first incomplete or
/// corrupt record and reports where: what `telesphere-mcap recover` keeps.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "robot/record/mcap_format.h"

namespace telesphere::record {

struct McapSchema {
  std::uint16_t id = 0;
  std::string name, encoding, data;
};

struct McapChannel {
  std::uint16_t id = 0, schema_id = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};

/// One message in place (data points into the file or the current chunk: valid during the callback).
struct McapMessageView {
  const McapChannel* channel = nullptr;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0, publish_time_ns = 0;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

/// An attachment in place (data valid during the callback); its CRC was checked.
struct McapAttachmentView {
  std::uint64_t log_time_ns = 0, create_time_ns = 0;
  std::string name, media_type;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

struct McapMetadata {
  std::string name;
  std::map<std::string, std::string> metadata;
};

struct McapSummary {
  std::string profile, library;
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
  std::uint64_t messages = 0, chunks = 0, attachments = 0, metadata = 0;
  std::uint64_t start_ns = 0, end_ns = 0;
  std::map<std::uint16_t, std::uint64_t> channel_messages;
  std::set<std::string> compressions;   ///< as named in the chunks ("" = none)
  bool from_summary_section = false;    ///< false: counted by reading the data section
  std::string summary_problem;          ///< why a summary section present was not used (its CRC, …)
};

/// Where and why a read stopped before the end of the data section.
struct McapDamage {
  std::uint64_t offset = 0;  ///< the first byte not kept
  std::string reason;
};

class McapReader {
 public:
  /// Maps `path` read-only; null with the reason.
  static std::unique_ptr<McapReader> open(const std::string& path, std::string* error);
  /// Over bytes the caller keeps alive (tests, the fuzzer).
  static std::unique_ptr<McapReader> fromBytes(const std::uint8_t* data, std::size_t size, std::string* error);
  ~McapReader();
  McapReader(const McapReader&) = delete;
  McapReader& operator=(const McapReader&) = delete;

  /// The summary section if the footer points at a valid one; otherwise (or with `scan` set)
  /// counted by reading every message (a damaged summary section is named in summary_problem).
  /// False with the reason on damage to the data section.
  bool summary(McapSummary* out, std::string* error, bool scan = false) const;

  using MessageCallback = std::function<bool(const McapMessageView&)>;  ///< false: stop reading
  /// Every message in file order with the schemas and channels seen so far. False with the
  /// reason (and *damage) at the first bad record, unless `stop_at_damage`: then true, and
  /// *damage (if given) says where the intact part ends (offset 0: the file is whole).
  bool forEachMessage(const MessageCallback& on_message, std::string* error, bool stop_at_damage = false,
                      McapDamage* damage = nullptr) const;

  /// What the data section holds besides messages, in file order, handed out as forEachMessage
  /// meets them (an attachment whose CRC does not hold is damage, like a chunk's).
  struct Extras {
    std::function<bool(const McapAttachmentView&)> on_attachment;  ///< false: stop reading
    std::function<bool(const McapMetadata&)> on_metadata;
  };
  bool forEachRecord(const MessageCallback& on_message, const Extras& extras, std::string* error,
                     bool stop_at_damage = false, McapDamage* damage = nullptr) const;

  const std::map<std::uint16_t, McapSchema>& schemasSeen() const { return schemas_; }
  const std::map<std::uint16_t, McapChannel>& channelsSeen() const { return channels_; }
  std::size_t fileSize() const { return size_; }

 private:
  McapReader(const std::uint8_t* data, std::size_t size, void* mapping);
  bool readSummarySection(McapSummary* out, std::string* error) const;

  const std::uint8_t* data_;
  std::size_t size_;
  void* mapping_;  ///< munmap'ed at destruction (null for fromBytes)
  mutable std::map<std::uint16_t, McapSchema> schemas_;
  mutable std::map<std::uint16_t, McapChannel> channels_;
};

}  // namespace telesphere::record
