// SPDX-License-Identifier: MIT
/// @brief Writes an MCAP file (mcap.dev/spec): schemas and channels as they are added, messages
///        in chunks (optionally compressed) each followed by its message indexes, metadata and
///        attachments between chunks, then at close() the data-end record, a summary (schemas,
///        channels, statistics, chunk, attachment and metadata indexes) with summary offsets, and
///        the footer; every CRC the format has is filled in.
///
/// A chunk is written whole with one write() once it holds `chunk_size` bytes (or flush() is
/// called), so a process that dies loses at most the chunk being filled; the file up to there
/// reads linearly, and `telesphere-mcap recover` finishes it (McapReader, mcapRecover).
/// Not thread-safe: one writer thread (record::LinkRecorder owns it).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "robot/record/mcap_format.h"

namespace telesphere::record {

struct McapWriterOptions {
  McapCompression compression = McapCompression::kNone;
  std::size_t chunk_size = 4u << 20;  ///< uncompressed bytes per chunk before it is written
  int zstd_level = 1;
  std::string profile;                ///< Header profile ("" : none; schemas say "protobuf")
  std::string library = "telesphere";
};

struct McapWriterStats {
  std::uint64_t messages = 0;
  std::uint64_t chunks = 0;
  std::uint64_t bytes_written = 0;       ///< file bytes so far
  std::uint64_t message_bytes = 0;       ///< payload bytes of the messages
};

class McapWriter {
 public:
  /// Creates `path`, which must not exist (never overwritten), and writes the magic and header;
  /// null with the reason.
  static std::unique_ptr<McapWriter> create(const std::string& path, const McapWriterOptions& options,
                                            std::string* error);
  /// Finishes the file (close()) unless that was done.
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A schema (`encoding` "protobuf": `data` is a serialized FileDescriptorSet, `name` the full
  /// message name); returns its id (1, 2, …), written at once. 0 after an I/O failure.
  std::uint16_t addSchema(const std::string& name, const std::string& encoding, const std::string& data);
  /// A channel on `topic` for messages of `schema_id`; returns its id (0, 1, …).
  std::uint16_t addChannel(const std::string& topic, std::uint16_t schema_id, const std::string& message_encoding,
                           const std::map<std::string, std::string>& metadata = {});

  /// One message (times in ns, `sequence` the publisher's own counter); false once the file
  /// cannot be written (error() says why; the writer then refuses everything).
  bool write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time_ns,
             std::uint64_t publish_time_ns, const void* data, std::size_t size);
  /// One message whose payload is `count` byte ranges one after the other (a header and a
  /// JPEG without joining them first).
  struct Part {
    const void* data;
    std::size_t size;
  };
  bool writeParts(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time_ns,
                  std::uint64_t publish_time_ns, const Part* parts, std::size_t count);
  /// A Metadata record (a name and a string map), e.g. which robot and software made the file.
  /// Written in the data section after the chunk being filled (flushed first, so the file stays
  /// in time order); indexed in the summary.
  bool writeMetadata(const std::string& name, const std::map<std::string, std::string>& metadata);
  /// An Attachment record: a file's bytes with its name and media type, at `log_time_ns` (e.g.
  /// the calibration in use, at the start and at each change); its CRC filled in; indexed.
  bool writeAttachment(std::uint64_t log_time_ns, std::uint64_t create_time_ns, const std::string& name,
                       const std::string& media_type, const void* data, std::size_t size);

  /// Writes the chunk being filled now (a message written before flush() survives a crash after it).
  bool flush();
  /// Last chunk, data end, summary, footer, magic; closes the file. Idempotent.
  bool close();

  const McapWriterStats& stats() const { return stats_; }
  const std::string& error() const { return error_; }

 private:
  McapWriter(int fd, McapWriterOptions options);
  bool writeOut(const std::vector<std::uint8_t>& bytes, bool counts_in_data_crc = true);
  bool fail(const std::string& what);
  void encodeSchema(McapEncoder& e, std::uint16_t id) const;
  void encodeChannel(McapEncoder& e, std::uint16_t id) const;

  struct Schema {
    std::string name, encoding, data;
  };
  struct Channel {
    std::string topic, message_encoding;
    std::uint16_t schema_id = 0;
    std::map<std::string, std::string> metadata;
  };
  struct ChunkIndex {
    std::uint64_t start_ns, end_ns, offset, length;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;
    std::uint64_t message_index_length, compressed_size, uncompressed_size;
  };

  int fd_;
  McapWriterOptions options_;
  std::string error_;
  bool closed_ = false;
  std::uint64_t offset_ = 0;
  std::uint32_t data_crc_ = 0;
  std::vector<Schema> schemas_;    ///< id = index + 1
  std::vector<Channel> channels_;  ///< id = index
  // The chunk being filled.
  std::vector<std::uint8_t> chunk_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;  ///< (log time, offset)
  std::uint64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0;
  std::vector<ChunkIndex> chunk_indexes_;
  struct AttachmentIndex {
    std::uint64_t offset, length, log_time_ns, create_time_ns, data_size;
    std::string name, media_type;
  };
  struct MetadataIndex {
    std::uint64_t offset, length;
    std::string name;
  };
  std::vector<AttachmentIndex> attachment_indexes_;
  std::vector<MetadataIndex> metadata_indexes_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t start_ns_ = 0, end_ns_ = 0;
  McapWriterStats stats_;
  std::vector<std::uint8_t> scratch_, compressed_;
};

}  // namespace telesphere::record
