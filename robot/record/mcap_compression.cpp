// SPDX-License-Identifier: MIT
/// @brief Zstandard and LZ4-frame chunk codecs (see mcap_compression.h).
#include "robot/record/mcap_compression.h"

#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>

namespace telesphere::record {

void compressChunk(McapCompression c, const std::uint8_t* data, std::size_t size, std::vector<std::uint8_t>* out,
                   int zstd_level) {
  switch (c) {
    case McapCompression::kNone: out->assign(data, data + size); return;
    case McapCompression::kZstd: {
      out->resize(ZSTD_compressBound(size));
      const std::size_t n = ZSTD_compress(out->data(), out->size(), data, size, zstd_level);
      out->resize(ZSTD_isError(n) ? 0 : n);  // cannot fail with a bound-sized buffer
      return;
    }
    case McapCompression::kLz4: {
      LZ4F_preferences_t prefs{};
      prefs.frameInfo.contentSize = size;  // lets a reader size its buffer
      out->resize(LZ4F_compressFrameBound(size, &prefs));
      const std::size_t n = LZ4F_compressFrame(out->data(), out->size(), data, size, &prefs);
      out->resize(LZ4F_isError(n) ? 0 : n);
      return;
    }
  }
}

bool decompressChunk(McapCompression c, const std::uint8_t* data, std::size_t size, std::uint64_t uncompressed_size,
                     std::vector<std::uint8_t>* out, std::string* error) {
  // A chunk claims its own size: refuse absurd claims before allocating (4 GiB).
  if (uncompressed_size > (std::uint64_t(1) << 32)) {
    *error = "chunk claims " + std::to_string(uncompressed_size) + " uncompressed bytes";
    return false;
  }
  switch (c) {
    case McapCompression::kNone:
      if (size != uncompressed_size) {
        *error = "uncompressed chunk of " + std::to_string(size) + " bytes claims " + std::to_string(uncompressed_size);
        return false;
      }
      out->assign(data, data + size);
      return true;
    case McapCompression::kZstd: {
      // Streamed into a buffer that grows with what actually comes out (a damaged chunk's claim
      // is not trusted with memory), never past the claim.
      ZSTD_DCtx* ctx = ZSTD_createDCtx();
      if (ctx == nullptr) {
        *error = "zstd: no decompression context";
        return false;
      }
      // One byte beyond the claim: a frame that ends exactly at the claim finishes with room to spare.
      const std::uint64_t cap = uncompressed_size + 1;
      out->resize(std::min<std::uint64_t>(cap, 4 * std::uint64_t(size) + 65536));
      ZSTD_inBuffer in{data, size, 0};
      std::size_t produced = 0;
      bool ok = true;
      for (;;) {
        ZSTD_outBuffer o{out->data(), out->size(), produced};
        const std::size_t rc = ZSTD_decompressStream(ctx, &o, &in);
        produced = o.pos;
        if (ZSTD_isError(rc)) {
          *error = std::string("zstd chunk: ") + ZSTD_getErrorName(rc);
          ok = false;
          break;
        }
        if (rc == 0 && in.pos == in.size) break;  // frame(s) complete
        if (o.pos < o.size && in.pos == in.size) {
          *error = "zstd chunk ends inside its frame";
          ok = false;
          break;
        }
        if (o.pos == o.size) {
          if (out->size() >= cap) {
            *error = "zstd chunk decompresses to more than the " + std::to_string(uncompressed_size) + " bytes it claims";
            ok = false;
            break;
          }
          out->resize(std::min<std::uint64_t>(cap, 2 * std::uint64_t(out->size())));
        }
      }
      ZSTD_freeDCtx(ctx);
      out->resize(std::min<std::size_t>(produced, out->size()));
      if (ok && produced != uncompressed_size) {
        *error = "zstd chunk decompressed to " + std::to_string(produced) + " bytes, claims " +
                 std::to_string(uncompressed_size);
        ok = false;
      }
      return ok;
    }
    case McapCompression::kLz4: {
      LZ4F_dctx* ctx = nullptr;
      if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) {
        *error = "lz4: no decompression context";
        return false;
      }
      const std::uint64_t cap = uncompressed_size + 1;
      out->resize(std::min<std::uint64_t>(cap, 4 * std::uint64_t(size) + 65536));
      std::size_t in_at = 0, out_at = 0;
      bool ok = true;
      for (;;) {
        if (out_at == out->size() && out->size() < cap)
          out->resize(std::min<std::uint64_t>(cap, 2 * std::uint64_t(out->size())));
        std::size_t in_n = size - in_at, out_n = out->size() - out_at;
        const std::size_t hint = LZ4F_decompress(ctx, out->data() + out_at, &out_n, data + in_at, &in_n, nullptr);
        if (LZ4F_isError(hint)) {
          *error = std::string("lz4 chunk: ") + LZ4F_getErrorName(hint);
          ok = false;
          break;
        }
        in_at += in_n;
        out_at += out_n;
        if (hint == 0) break;  // frame complete
        if (in_n == 0 && out_n == 0) {
          *error = out_at >= uncompressed_size ? "lz4 chunk decompresses to more than it claims"
                                               : "lz4 chunk ends inside its frame";
          ok = false;
          break;
        }
      }
      LZ4F_freeDecompressionContext(ctx);
      if (ok && out_at != uncompressed_size) {
        *error = "lz4 chunk decompressed to " + std::to_string(out_at) + " bytes, claims " +
                 std::to_string(uncompressed_size);
        ok = false;
      }
      out->resize(out_at);
      return ok;
    }
  }
  *error = "unknown compression";
  return false;
}

}  // namespace telesphere::record
