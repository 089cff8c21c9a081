// SPDX-License-Identifier: MIT
/// @brief McapReader (see mcap_reader.h).
#include "robot/record/mcap_reader.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "robot/record/mcap_compression.h"

namespace telesphere::record {
namespace {

constexpr std::size_t kRecordHead = 9;   // opcode + u64 length
constexpr std::size_t kFooterContent = 20;

bool parseMap(McapDecoder& d, std::map<std::string, std::string>* out) {
  const std::uint32_t bytes = d.u32();
  const std::uint8_t* at = d.bytes(bytes);
  if (at == nullptr) return false;
  McapDecoder m(at, bytes);
  while (m.ok() && m.remaining() > 0) {
    std::string k = m.str();
    std::string v = m.str();
    if (m.ok()) (*out)[std::move(k)] = std::move(v);
  }
  return m.ok();
}

bool parseSchema(const std::uint8_t* p, std::size_t n, McapSchema* s) {
  McapDecoder d(p, n);
  s->id = d.u16();
  s->name = d.str();
  s->encoding = d.str();
  s->data = d.str();
  return d.ok() && s->id != 0;  // id 0 is reserved ("no schema")
}

bool parseChannel(const std::uint8_t* p, std::size_t n, McapChannel* c) {
  McapDecoder d(p, n);
  c->id = d.u16();
  c->schema_id = d.u16();
  c->topic = d.str();
  c->message_encoding = d.str();
  return d.ok() && parseMap(d, &c->metadata);
}

/// A message record's fields; data in place.
bool parseMessage(const std::uint8_t* p, std::size_t n, std::uint16_t* channel, McapMessageView* m) {
  McapDecoder d(p, n);
  *channel = d.u16();
  m->sequence = d.u32();
  m->log_time_ns = d.u64();
  m->publish_time_ns = d.u64();
  if (!d.ok()) return false;
  m->size = d.remaining();
  m->data = d.position();
  return true;
}

std::string at(std::uint64_t offset) { return " at byte " + std::to_string(offset); }

}  // namespace

McapReader::McapReader(const std::uint8_t* data, std::size_t size, void* mapping)
    : data_(data), size_(size), mapping_(mapping) {}

McapReader::~McapReader() {
  if (mapping_ != nullptr) ::munmap(mapping_, size_);
}

std::unique_ptr<McapReader> McapReader::fromBytes(const std::uint8_t* data, std::size_t size, std::string* error) {
  if (size < kMcapMagic.size() || std::memcmp(data, kMcapMagic.data(), kMcapMagic.size()) != 0) {
    *error = "not an MCAP file (no MCAP magic at its start)";
    return nullptr;
  }
  return std::unique_ptr<McapReader>(new McapReader(data, size, nullptr));
}

std::unique_ptr<McapReader> McapReader::open(const std::string& path, std::string* error) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    *error = "cannot open " + path + ": " + std::strerror(errno);
    return nullptr;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || st.st_size <= 0) {
    *error = path + ": empty or unreadable";
    ::close(fd);
    return nullptr;
  }
  const auto size = static_cast<std::size_t>(st.st_size);
  void* map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (map == MAP_FAILED) {
    *error = "cannot map " + path + ": " + std::strerror(errno);
    return nullptr;
  }
  const auto* bytes = static_cast<const std::uint8_t*>(map);
  if (size < kMcapMagic.size() || std::memcmp(bytes, kMcapMagic.data(), kMcapMagic.size()) != 0) {
    ::munmap(map, size);
    *error = path + ": not an MCAP file (no MCAP magic at its start)";
    return nullptr;
  }
  return std::unique_ptr<McapReader>(new McapReader(bytes, size, map));
}

bool McapReader::forEachMessage(const MessageCallback& on_message, std::string* error, bool stop_at_damage,
                                McapDamage* damage) const {
  return forEachRecord(on_message, {}, error, stop_at_damage, damage);
}

bool McapReader::forEachRecord(const MessageCallback& on_message, const Extras& extras, std::string* error,
                               bool stop_at_damage, McapDamage* damage) const {
  schemas_.clear();
  channels_.clear();
  McapDamage where;
  // Records damage at `offset`; with stop_at_damage the intact part before it is the result.
  const auto damaged = [&](std::uint64_t offset, const std::string& reason) {
    where = {offset, reason};
    if (damage != nullptr) *damage = where;
    *error = reason + at(offset);
    return stop_at_damage;
  };
  std::size_t pos = kMcapMagic.size();
  std::uint32_t crc = mcapCrc32(data_, pos);
  bool header_seen = false;
  std::vector<std::uint8_t> chunk_bytes;
  struct Pending {
    std::uint16_t channel;
    McapMessageView view;
  };
  std::vector<Pending> pending;
  // Schema, channel and message records, at the top level or inside a chunk: one set of rules.
  // A message waits in `pending` until its record (or its whole chunk) has been checked.
  const auto take = [&](McapOp op, const std::uint8_t* p, std::size_t n, const char* where) -> std::string {
    if (op == McapOp::kSchema) {
      McapSchema schema;
      if (!parseSchema(p, n, &schema)) return std::string("malformed schema record") + where;
      schemas_[schema.id] = std::move(schema);
    } else if (op == McapOp::kChannel) {
      McapChannel c;
      if (!parseChannel(p, n, &c)) return std::string("malformed channel record") + where;
      if (c.schema_id != 0 && schemas_.count(c.schema_id) == 0)
        return "channel " + c.topic + " names schema " + std::to_string(c.schema_id) + " before its record";
      channels_[c.id] = std::move(c);
    } else {
      Pending m{};
      if (!parseMessage(p, n, &m.channel, &m.view)) return std::string("malformed message record") + where;
      if (channels_.count(m.channel) == 0)
        return "a message on channel " + std::to_string(m.channel) + " before its channel record";
      pending.push_back(m);
    }
    return {};
  };
  // False when the caller asked to stop.
  const auto handOut = [&] {
    for (Pending& m : pending) {
      m.view.channel = &channels_.at(m.channel);
      if (!on_message(m.view)) return false;
    }
    pending.clear();
    return true;
  };
  for (;;) {
    if (pos == size_) return damaged(pos, "the file ends without its data end record (cut off while recording?)");
    if (size_ - pos < kRecordHead) return damaged(pos, "the file ends inside a record");
    McapDecoder head(data_ + pos, kRecordHead);
    const auto op = static_cast<McapOp>(head.u8());
    const std::uint64_t length = head.u64();
    if (length > size_ - pos - kRecordHead)
      return damaged(pos, "a record claims " + std::to_string(length) + " bytes, the file has " +
                              std::to_string(size_ - pos - kRecordHead) + " left (cut off while recording?)");
    const std::uint8_t* content = data_ + pos + kRecordHead;
    const auto n = static_cast<std::size_t>(length);
    if (!header_seen && op != McapOp::kHeader) return damaged(pos, "the first record is not a header");
    switch (op) {
      case McapOp::kHeader: header_seen = true; break;
      case McapOp::kSchema:
      case McapOp::kChannel:
      case McapOp::kMessage: {
        pending.clear();
        if (const std::string why = take(op, content, n, ""); !why.empty()) return damaged(pos, why);
        if (!handOut()) return true;
        break;
      }
      case McapOp::kChunk: {
        McapDecoder d(content, n);
        d.u64();  // start and end times: not needed to read
        d.u64();
        const std::uint64_t uncompressed_size = d.u64();
        const std::uint32_t uncompressed_crc = d.u32();
        const std::string compression_name = d.str();
        const std::uint64_t records_size = d.u64();
        const std::uint8_t* records = d.bytes(records_size);
        if (!d.ok() || records == nullptr) return damaged(pos, "malformed chunk record");
        const auto compression = parseCompression(compression_name);
        if (!compression) return damaged(pos, "chunk compressed with unknown \"" + compression_name + "\"");
        std::string why;
        const std::uint8_t* plain = records;
        std::size_t plain_size = static_cast<std::size_t>(records_size);
        if (*compression != McapCompression::kNone) {
          if (!decompressChunk(*compression, records, plain_size, uncompressed_size, &chunk_bytes, &why))
            return damaged(pos, why);
          plain = chunk_bytes.data();
          plain_size = chunk_bytes.size();
        } else if (records_size != uncompressed_size) {
          return damaged(pos, "uncompressed chunk whose sizes differ");
        }
        if (uncompressed_crc != 0 && mcapCrc32(plain, plain_size) != uncompressed_crc)
          return damaged(pos, "chunk CRC mismatch (the chunk's bytes are corrupt)");
        // The whole chunk is checked before any of its messages is handed out.
        pending.clear();
        std::size_t in = 0;
        while (in < plain_size) {
          if (plain_size - in < kRecordHead) return damaged(pos, "a chunk ends inside a record");
          McapDecoder rh(plain + in, kRecordHead);
          const auto inner_op = static_cast<McapOp>(rh.u8());
          const std::uint64_t inner_length = rh.u64();
          if (inner_length > plain_size - in - kRecordHead) return damaged(pos, "a record in a chunk overruns it");
          const std::uint8_t* ic = plain + in + kRecordHead;
          const auto inner_n = static_cast<std::size_t>(inner_length);
          if (inner_op != McapOp::kSchema && inner_op != McapOp::kChannel && inner_op != McapOp::kMessage)
            return damaged(pos, "a chunk holds a record of type " + std::to_string(int(inner_op)));
          if (const std::string why = take(inner_op, ic, inner_n, " in a chunk"); !why.empty()) return damaged(pos, why);
          in += kRecordHead + inner_n;
        }
        if (!handOut()) return true;
        break;
      }
      case McapOp::kDataEnd: {
        McapDecoder d(content, n);
        const std::uint32_t want = d.u32();
        if (!d.ok()) return damaged(pos, "malformed data end record");
        if (want != 0 && want != crc) return damaged(pos, "data section CRC mismatch");
        if (damage != nullptr) *damage = {};
        return true;
      }
      case McapOp::kFooter:
        return damaged(pos, "a footer before the data end record");
      case McapOp::kAttachment: {
        McapDecoder d(content, n);
        McapAttachmentView a;
        a.log_time_ns = d.u64();
        a.create_time_ns = d.u64();
        a.name = d.str();
        a.media_type = d.str();
        const std::uint64_t data_size = d.u64();
        a.data = d.bytes(data_size);
        const std::size_t crc_at = n >= 4 ? n - 4 : 0;
        const std::uint32_t want = d.u32();
        if (!d.ok() || a.data == nullptr || d.remaining() != 0) return damaged(pos, "malformed attachment record");
        if (want != 0 && mcapCrc32(content, crc_at) != want)
          return damaged(pos, "attachment CRC mismatch (" + a.name + ")");
        a.size = static_cast<std::size_t>(data_size);
        if (extras.on_attachment && !extras.on_attachment(a)) return true;
        break;
      }
      case McapOp::kMetadata: {
        McapDecoder d(content, n);
        McapMetadata m;
        m.name = d.str();
        const std::uint32_t bytes = d.u32();
        const std::uint8_t* map = d.bytes(bytes);
        if (!d.ok() || map == nullptr) return damaged(pos, "malformed metadata record");
        McapDecoder md(map, bytes);
        while (md.ok() && md.remaining() > 0) {
          std::string key = md.str();
          std::string value = md.str();
          if (md.ok()) m.metadata[std::move(key)] = std::move(value);
        }
        if (!md.ok()) return damaged(pos, "malformed metadata record (" + m.name + ")");
        if (extras.on_metadata && !extras.on_metadata(m)) return true;
        break;
      }
      default: break;  // indexes and opcodes of later versions: skipped
    }
    crc = mcapCrc32(data_ + pos, kRecordHead + n, crc);
    pos += kRecordHead + n;
  }
}

bool McapReader::readSummarySection(McapSummary* out, std::string* error) const {
  const std::size_t tail = kRecordHead + kFooterContent + kMcapMagic.size();
  if (size_ < kMcapMagic.size() + tail) return false;
  const std::uint8_t* end_magic = data_ + size_ - kMcapMagic.size();
  if (std::memcmp(end_magic, kMcapMagic.data(), kMcapMagic.size()) != 0) return false;
  const std::size_t footer_at = size_ - tail;
  McapDecoder f(data_ + footer_at, kRecordHead + kFooterContent);
  if (f.u8() != std::uint8_t(McapOp::kFooter) || f.u64() != kFooterContent) return false;
  const std::uint64_t summary_start = f.u64();
  const std::uint64_t summary_offset_start = f.u64();
  const std::uint32_t summary_crc = f.u32();
  if (summary_start == 0) return false;  // written without a summary
  if (summary_start < kMcapMagic.size() || summary_start > footer_at ||
      (summary_offset_start != 0 && (summary_offset_start < summary_start || summary_offset_start > footer_at))) {
    *error = "the footer points outside the file";
    return false;
  }
  if (summary_crc != 0 &&
      mcapCrc32(data_ + summary_start, footer_at + kRecordHead + 16 - summary_start) != summary_crc) {
    *error = "summary CRC mismatch";
    return false;
  }
  const std::size_t end = summary_offset_start != 0 ? summary_offset_start : footer_at;
  std::size_t pos = summary_start;
  bool statistics = false;
  while (pos < end) {
    if (end - pos < kRecordHead) return false;
    McapDecoder head(data_ + pos, kRecordHead);
    const auto op = static_cast<McapOp>(head.u8());
    const std::uint64_t length = head.u64();
    if (length > end - pos - kRecordHead) return false;
    const std::uint8_t* c = data_ + pos + kRecordHead;
    const auto n = static_cast<std::size_t>(length);
    if (op == McapOp::kSchema) {
      McapSchema s;
      if (!parseSchema(c, n, &s)) return false;
      out->schemas[s.id] = std::move(s);
    } else if (op == McapOp::kChannel) {
      McapChannel ch;
      if (!parseChannel(c, n, &ch)) return false;
      out->channels[ch.id] = std::move(ch);
    } else if (op == McapOp::kStatistics) {
      McapDecoder d(c, n);
      out->messages = d.u64();
      d.u16();
      d.u32();
      out->attachments = d.u32();
      out->metadata = d.u32();
      out->chunks = d.u32();
      out->start_ns = d.u64();
      out->end_ns = d.u64();
      const std::uint32_t bytes = d.u32();
      const std::uint8_t* m = d.bytes(bytes);
      if (!d.ok() || m == nullptr) return false;
      McapDecoder md(m, bytes);
      while (md.ok() && md.remaining() > 0) {
        const std::uint16_t channel = md.u16();
        const std::uint64_t count = md.u64();
        if (md.ok()) out->channel_messages[channel] = count;
      }
      if (!md.ok()) return false;
      statistics = true;
    } else if (op == McapOp::kChunkIndex) {
      McapDecoder d(c, n);
      for (int i = 0; i < 4; ++i) d.u64();
      const std::uint32_t bytes = d.u32();
      d.bytes(bytes);
      d.u64();
      const std::string compression = d.str();
      if (!d.ok()) return false;
      out->compressions.insert(compression);
    }
    pos += kRecordHead + n;
  }
  out->from_summary_section = statistics;
  return statistics;
}

bool McapReader::summary(McapSummary* out, std::string* error, bool scan) const {
  *out = {};
  McapDecoder h(data_ + kMcapMagic.size(), size_ - kMcapMagic.size());
  if (h.u8() == std::uint8_t(McapOp::kHeader)) {
    const std::uint64_t length = h.u64();
    const std::uint8_t* c = h.bytes(length);
    if (c != nullptr) {
      McapDecoder hd(c, static_cast<std::size_t>(length));
      out->profile = hd.str();
      out->library = hd.str();
    }
  }
  if (!scan) {
    std::string why;
    McapSummary from_section = *out;
    if (readSummarySection(&from_section, &why)) {
      *out = std::move(from_section);
      return true;
    }
    // A damaged summary (its CRC, the footer) does not make the messages unreadable: count them.
    out->summary_problem = why;
  }
  // No (usable) summary section: count by reading, and name the chunks' compressions on the way.
  const std::string summary_problem = out->summary_problem;
  bool first = true;
  Extras extras;
  extras.on_attachment = [&](const McapAttachmentView&) { return ++out->attachments, true; };
  extras.on_metadata = [&](const McapMetadata&) { return ++out->metadata, true; };
  const bool ok = forEachRecord(
      [&](const McapMessageView& m) {
        if (first || m.log_time_ns < out->start_ns) out->start_ns = m.log_time_ns;
        if (first || m.log_time_ns > out->end_ns) out->end_ns = m.log_time_ns;
        first = false;
        ++out->messages;
        ++out->channel_messages[m.channel->id];
        return true;
      },
      extras, error);
  out->schemas = schemas_;
  out->channels = channels_;
  out->summary_problem = summary_problem;
  // Chunks and their compressions, from the record headers (cheap: no decompression).
  std::size_t pos = kMcapMagic.size();
  while (size_ - pos >= kRecordHead) {
    McapDecoder head(data_ + pos, kRecordHead);
    const auto op = static_cast<McapOp>(head.u8());
    const std::uint64_t length = head.u64();
    if (length > size_ - pos - kRecordHead || op == McapOp::kDataEnd) break;
    if (op == McapOp::kChunk) {
      McapDecoder d(data_ + pos + kRecordHead, static_cast<std::size_t>(length));
      for (int i = 0; i < 3; ++i) d.u64();
      d.u32();
      const std::string compression = d.str();
      if (d.ok()) out->compressions.insert(compression);
      ++out->chunks;
    }
    pos += kRecordHead + static_cast<std::size_t>(length);
  }
  return ok;
}

}  // namespace telesphere::record
