// SPDX-License-Identifier: MIT
/// @brief The MCAP container as the public specification (mcap.dev/spec, major version 0) lays
///        it out: magic, record opcodes, compression names, and the little-endian field codec
///        the writer and reader share.
///
///   <magic><Header><data section: Schema, Channel, Chunk + MessageIndex…, DataEnd>
///   <summary: Schema…, Channel…, Statistics, ChunkIndex…><summary offsets…><Footer><magic>
///
/// Every record is <opcode u8><content length u64><content>. Strings and byte fields are
/// prefixed by a u32 length, maps by a u32 byte length, a Chunk's records by a u64 length.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace telesphere::record {

inline constexpr std::array<std::uint8_t, 8> kMcapMagic{0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};

enum class McapOp : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// Chunk compression: none, Zstandard, or LZ4 frames (the spec's "", "zstd", "lz4").
enum class McapCompression { kNone, kZstd, kLz4 };
std::string_view compressionName(McapCompression c);
/// From the name in a file or on a command line ("" or "none", "zstd", "lz4").
std::optional<McapCompression> parseCompression(std::string_view name);

/// CRC-32 (ISO-HDLC, as zlib), continued from `crc` (0 to start).
std::uint32_t mcapCrc32(const void* data, std::size_t size, std::uint32_t crc = 0);

/// Appends little-endian fields to a record being built.
class McapEncoder {
 public:
  explicit McapEncoder(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { le(v, 2); }
  void u32(std::uint32_t v) { le(v, 4); }
  void u64(std::uint64_t v) { le(v, 8); }
  void str(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  void raw(const void* data, std::size_t size) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    out_.insert(out_.end(), p, p + size);
  }
  /// Starts a record; finish it with endRecord(returned position).
  std::size_t beginRecord(McapOp op) {
    u8(static_cast<std::uint8_t>(op));
    const std::size_t at = out_.size();
    u64(0);
    return at;
  }
  void endRecord(std::size_t at) {
    const std::uint64_t length = out_.size() - at - 8;
    for (int i = 0; i < 8; ++i) out_[at + std::size_t(i)] = static_cast<std::uint8_t>(length >> (8 * i));
  }
  /// Patches a u32 length written as a placeholder at `at` with the bytes after it.
  void patchU32Length(std::size_t at) {
    const auto length = static_cast<std::uint32_t>(out_.size() - at - 4);
    for (int i = 0; i < 4; ++i) out_[at + std::size_t(i)] = static_cast<std::uint8_t>(length >> (8 * i));
  }
  std::size_t size() const { return out_.size(); }

 private:
  void le(std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t>& out_;
};

/// Reads little-endian fields from a record's content; every read checks the bounds, and after
/// the first failure ok() stays false and reads return zeros (callers check ok() once).
class McapDecoder {
 public:
  McapDecoder(const std::uint8_t* data, std::size_t size) : p_(data), end_(data + size) {}
  std::uint8_t u8() { return static_cast<std::uint8_t>(le(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(le(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(le(4)); }
  std::uint64_t u64() { return le(8); }
  std::string str() {
    const std::uint32_t n = u32();
    if (!need(n)) return {};
    std::string s(reinterpret_cast<const char*>(p_), n);
    p_ += n;
    return s;
  }
  /// `n` bytes in place (null when fewer remain).
  const std::uint8_t* bytes(std::uint64_t n) {
    if (!need(n)) return nullptr;
    const std::uint8_t* at = p_;
    p_ += n;
    return at;
  }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  const std::uint8_t* position() const { return p_; }
  bool ok() const { return ok_; }

 private:
  bool need(std::uint64_t n) {
    if (!ok_ || n > remaining()) {
      ok_ = false;
      return false;
    }
    return true;
  }
  std::uint64_t le(int bytes) {
    if (!need(std::uint64_t(bytes))) return 0;
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= std::uint64_t(p_[i]) << (8 * i);
    p_ += bytes;
    return v;
  }
  const std::uint8_t* p_;
  const std::uint8_t* end_;
  bool ok_ = true;
};

}  // namespace telesphere::record
