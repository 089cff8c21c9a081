// SPDX-License-Identifier: MIT
/// @brief McapWriter (see mcap_writer.h).
#include "robot/record/mcap_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "robot/record/mcap_compression.h"

namespace telesphere::record {

std::unique_ptr<McapWriter> McapWriter::create(const std::string& path, const McapWriterOptions& options,
                                               std::string* error) {
  // O_EXCL: a recording is never written over a file (nor over the file a caller reads from).
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    *error = errno == EEXIST ? path + " exists: a recording never overwrites a file"
                             : "cannot create " + path + ": " + std::strerror(errno);
    return nullptr;
  }
  std::unique_ptr<McapWriter> w(new McapWriter(fd, options));
  std::vector<std::uint8_t> head(kMcapMagic.begin(), kMcapMagic.end());
  McapEncoder e(head);
  const std::size_t at = e.beginRecord(McapOp::kHeader);
  e.str(options.profile);
  e.str(options.library);
  e.endRecord(at);
  if (!w->writeOut(head)) {
    *error = path + ": " + w->error_;
    return nullptr;
  }
  return w;
}

McapWriter::McapWriter(int fd, McapWriterOptions options) : fd_(fd), options_(std::move(options)) {
  if (options_.chunk_size == 0) options_.chunk_size = 1;
}

McapWriter::~McapWriter() {
  close();
  if (fd_ >= 0) ::close(fd_);
}

bool McapWriter::fail(const std::string& what) {
  if (error_.empty()) error_ = what;
  return false;
}

bool McapWriter::writeOut(const std::vector<std::uint8_t>& bytes, bool counts_in_data_crc) {
  if (!error_.empty()) return false;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return fail(std::string("write failed: ") + (n < 0 ? std::strerror(errno) : "no progress"));
    done += std::size_t(n);
  }
  if (counts_in_data_crc) data_crc_ = mcapCrc32(bytes.data(), bytes.size(), data_crc_);
  offset_ += bytes.size();
  stats_.bytes_written = offset_;
  return true;
}

void McapWriter::encodeSchema(McapEncoder& e, std::uint16_t id) const {
  const Schema& s = schemas_[id - 1u];
  const std::size_t at = e.beginRecord(McapOp::kSchema);
  e.u16(id);
  e.str(s.name);
  e.str(s.encoding);
  e.str(s.data);  // u32-prefixed bytes
  e.endRecord(at);
}

void McapWriter::encodeChannel(McapEncoder& e, std::uint16_t id) const {
  const Channel& c = channels_[id];
  const std::size_t at = e.beginRecord(McapOp::kChannel);
  e.u16(id);
  e.u16(c.schema_id);
  e.str(c.topic);
  e.str(c.message_encoding);
  const std::size_t map_at = e.size();
  e.u32(0);
  for (const auto& [k, v] : c.metadata) {
    e.str(k);
    e.str(v);
  }
  e.patchU32Length(map_at);
  e.endRecord(at);
}

std::uint16_t McapWriter::addSchema(const std::string& name, const std::string& encoding, const std::string& data) {
  if (closed_ || !error_.empty() || schemas_.size() >= 0xFFFE) return 0;
  schemas_.push_back({name, encoding, data});
  const auto id = static_cast<std::uint16_t>(schemas_.size());
  scratch_.clear();
  McapEncoder e(scratch_);
  encodeSchema(e, id);
  return writeOut(scratch_) ? id : 0;
}

std::uint16_t McapWriter::addChannel(const std::string& topic, std::uint16_t schema_id,
                                     const std::string& message_encoding,
                                     const std::map<std::string, std::string>& metadata) {
  if (closed_ || !error_.empty() || channels_.size() >= 0xFFFF) return 0xFFFF;
  channels_.push_back({topic, message_encoding, schema_id, metadata});
  const auto id = static_cast<std::uint16_t>(channels_.size() - 1);
  scratch_.clear();
  McapEncoder e(scratch_);
  encodeChannel(e, id);
  return writeOut(scratch_) ? id : 0xFFFF;
}

bool McapWriter::write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time_ns,
                       std::uint64_t publish_time_ns, const void* data, std::size_t size) {
  const Part part{data, size};
  return writeParts(channel_id, sequence, log_time_ns, publish_time_ns, &part, 1);
}

bool McapWriter::writeParts(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time_ns,
                            std::uint64_t publish_time_ns, const Part* parts, std::size_t count) {
  if (closed_) return fail("write after close");
  if (!error_.empty()) return false;
  if (channel_id >= channels_.size()) return fail("message on unknown channel " + std::to_string(channel_id));
  if (chunk_.empty()) chunk_start_ns_ = chunk_end_ns_ = log_time_ns;
  chunk_start_ns_ = std::min(chunk_start_ns_, log_time_ns);
  chunk_end_ns_ = std::max(chunk_end_ns_, log_time_ns);
  chunk_index_[channel_id].emplace_back(log_time_ns, chunk_.size());
  McapEncoder e(chunk_);
  const std::size_t at = e.beginRecord(McapOp::kMessage);
  e.u16(channel_id);
  e.u32(sequence);
  e.u64(log_time_ns);
  e.u64(publish_time_ns);
  std::size_t size = 0;
  for (std::size_t i = 0; i < count; ++i) {
    e.raw(parts[i].data, parts[i].size);
    size += parts[i].size;
  }
  e.endRecord(at);
  if (stats_.messages == 0) start_ns_ = end_ns_ = log_time_ns;
  start_ns_ = std::min(start_ns_, log_time_ns);
  end_ns_ = std::max(end_ns_, log_time_ns);
  ++stats_.messages;
  stats_.message_bytes += size;
  ++channel_counts_[channel_id];
  return chunk_.size() >= options_.chunk_size ? flush() : true;
}

bool McapWriter::writeMetadata(const std::string& name, const std::map<std::string, std::string>& metadata) {
  if (closed_) return fail("metadata after close");
  if (!flush()) return false;
  scratch_.clear();
  McapEncoder e(scratch_);
  const std::size_t at = e.beginRecord(McapOp::kMetadata);
  e.str(name);
  const std::size_t map_at = e.size();
  e.u32(0);
  for (const auto& [k, v] : metadata) {  // std::map: keys sorted, as the spec asks of maps
    e.str(k);
    e.str(v);
  }
  e.patchU32Length(map_at);
  e.endRecord(at);
  const MetadataIndex index{offset_, scratch_.size(), name};
  if (!writeOut(scratch_)) return false;
  metadata_indexes_.push_back(index);
  return true;
}

bool McapWriter::writeAttachment(std::uint64_t log_time_ns, std::uint64_t create_time_ns, const std::string& name,
                                 const std::string& media_type, const void* data, std::size_t size) {
  if (closed_) return fail("attachment after close");
  if (!flush()) return false;
  scratch_.clear();
  McapEncoder e(scratch_);
  const std::size_t at = e.beginRecord(McapOp::kAttachment);
  const std::size_t fields = e.size();
  e.u64(log_time_ns);
  e.u64(create_time_ns);
  e.str(name);
  e.str(media_type);
  e.u64(size);
  e.raw(data, size);
  e.u32(mcapCrc32(scratch_.data() + fields, scratch_.size() - fields));  // the fields before it
  e.endRecord(at);
  const AttachmentIndex index{offset_, scratch_.size(), log_time_ns, create_time_ns, size, name, media_type};
  if (!writeOut(scratch_)) return false;
  attachment_indexes_.push_back(index);
  return true;
}

bool McapWriter::flush() {
  if (!error_.empty()) return false;
  if (chunk_.empty()) return true;
  compressChunk(options_.compression, chunk_.data(), chunk_.size(), &compressed_, options_.zstd_level);
  if (compressed_.empty() && !chunk_.empty()) return fail("chunk compression failed");
  scratch_.clear();
  McapEncoder e(scratch_);
  ChunkIndex index{};
  index.start_ns = chunk_start_ns_;
  index.end_ns = chunk_end_ns_;
  index.offset = offset_;
  const std::size_t at = e.beginRecord(McapOp::kChunk);
  e.u64(chunk_start_ns_);
  e.u64(chunk_end_ns_);
  e.u64(chunk_.size());
  e.u32(mcapCrc32(chunk_.data(), chunk_.size()));
  e.str(compressionName(options_.compression));
  e.u64(compressed_.size());
  e.raw(compressed_.data(), compressed_.size());
  e.endRecord(at);
  index.length = scratch_.size();
  index.compressed_size = compressed_.size();
  index.uncompressed_size = chunk_.size();
  // The message indexes, one record per channel, right after the chunk.
  for (const auto& [channel, entries] : chunk_index_) {
    index.message_index_offsets[channel] = offset_ + scratch_.size();
    const std::size_t mat = e.beginRecord(McapOp::kMessageIndex);
    e.u16(channel);
    e.u32(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, off] : entries) {
      e.u64(t);
      e.u64(off);
    }
    e.endRecord(mat);
  }
  index.message_index_length = scratch_.size() - index.length;
  if (!writeOut(scratch_)) return false;
  chunk_indexes_.push_back(std::move(index));
  ++stats_.chunks;
  chunk_.clear();
  chunk_index_.clear();
  return true;
}

bool McapWriter::close() {
  if (closed_) return error_.empty();
  if (!flush()) {
    closed_ = true;
    return false;
  }
  closed_ = true;
  std::vector<std::uint8_t> out;
  McapEncoder e(out);
  std::size_t at = e.beginRecord(McapOp::kDataEnd);
  e.u32(data_crc_);
  e.endRecord(at);
  if (!writeOut(out, false)) return false;

  // Summary: groups of records, each group's place remembered for the summary offsets.
  const std::uint64_t summary_start = offset_;
  out.clear();
  struct Group {
    McapOp op;
    std::uint64_t start, length;
  };
  std::vector<Group> groups;
  const auto group = [&](McapOp op, const auto& body) {
    const std::size_t begin = out.size();
    body();
    if (out.size() > begin) groups.push_back({op, summary_start + begin, out.size() - begin});
  };
  group(McapOp::kSchema, [&] {
    for (std::size_t i = 0; i < schemas_.size(); ++i) encodeSchema(e, static_cast<std::uint16_t>(i + 1));
  });
  group(McapOp::kChannel, [&] {
    for (std::size_t i = 0; i < channels_.size(); ++i) encodeChannel(e, static_cast<std::uint16_t>(i));
  });
  group(McapOp::kStatistics, [&] {
    const std::size_t s = e.beginRecord(McapOp::kStatistics);
    e.u64(stats_.messages);
    e.u16(static_cast<std::uint16_t>(schemas_.size()));
    e.u32(static_cast<std::uint32_t>(channels_.size()));
    e.u32(static_cast<std::uint32_t>(attachment_indexes_.size()));
    e.u32(static_cast<std::uint32_t>(metadata_indexes_.size()));
    e.u32(static_cast<std::uint32_t>(chunk_indexes_.size()));
    e.u64(start_ns_);
    e.u64(end_ns_);
    const std::size_t map_at = e.size();
    e.u32(0);
    for (const auto& [channel, count] : channel_counts_) {
      e.u16(channel);
      e.u64(count);
    }
    e.patchU32Length(map_at);
    e.endRecord(s);
  });
  group(McapOp::kChunkIndex, [&] {
    for (const ChunkIndex& c : chunk_indexes_) {
      const std::size_t s = e.beginRecord(McapOp::kChunkIndex);
      e.u64(c.start_ns);
      e.u64(c.end_ns);
      e.u64(c.offset);
      e.u64(c.length);
      const std::size_t map_at = e.size();
      e.u32(0);
      for (const auto& [channel, off] : c.message_index_offsets) {
        e.u16(channel);
        e.u64(off);
      }
      e.patchU32Length(map_at);
      e.u64(c.message_index_length);
      e.str(compressionName(options_.compression));
      e.u64(c.compressed_size);
      e.u64(c.uncompressed_size);
      e.endRecord(s);
    }
  });
  group(McapOp::kAttachmentIndex, [&] {
    for (const AttachmentIndex& a : attachment_indexes_) {
      const std::size_t s = e.beginRecord(McapOp::kAttachmentIndex);
      e.u64(a.offset);
      e.u64(a.length);
      e.u64(a.log_time_ns);
      e.u64(a.create_time_ns);
      e.u64(a.data_size);
      e.str(a.name);
      e.str(a.media_type);
      e.endRecord(s);
    }
  });
  group(McapOp::kMetadataIndex, [&] {
    for (const MetadataIndex& m : metadata_indexes_) {
      const std::size_t s = e.beginRecord(McapOp::kMetadataIndex);
      e.u64(m.offset);
      e.u64(m.length);
      e.str(m.name);
      e.endRecord(s);
    }
  });
  const std::uint64_t summary_offset_start = summary_start + out.size();
  for (const Group& g : groups) {
    const std::size_t s = e.beginRecord(McapOp::kSummaryOffset);
    e.u8(static_cast<std::uint8_t>(g.op));
    e.u64(g.start);
    e.u64(g.length);
    e.endRecord(s);
  }
  e.u8(static_cast<std::uint8_t>(McapOp::kFooter));
  e.u64(20);  // the footer's content length, in the CRC below
  e.u64(summary_start);
  e.u64(summary_offset_start);
  e.u32(mcapCrc32(out.data(), out.size()));  // the summary, its offsets and the footer up to here
  out.insert(out.end(), kMcapMagic.begin(), kMcapMagic.end());
  if (!writeOut(out, false)) return false;
  if (::fsync(fd_) != 0) return fail(std::string("fsync failed: ") + std::strerror(errno));
  return true;
}

}  // namespace telesphere::record
