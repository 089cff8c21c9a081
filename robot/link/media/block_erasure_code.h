// SPDX-License-Identifier: MIT
/// @brief Forward error correction for the media path (DESIGN.md §9): a Reed–Solomon erasure code
///        over GF(2⁸) with a Cauchy generator matrix, by Intel's ISA-L (Debian: libisal). A block
///        of k equal-size data shards gets r parity shards; any k of the k + r shards give the
///        data back. We only arrange shards and matrices here; the arithmetic is ISA-L's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace telesphere::link::media {

class BlockErasureCode {
 public:
  /// 1 ≤ k, 0 ≤ r, k + r ≤ 255 (throws std::invalid_argument otherwise).
  BlockErasureCode(int k, int r);

  int dataShards() const { return k_; }
  int parityShards() const { return r_; }

  /// Writes the r parity shards from the k data shards, every shard `bytes` long.
  void encode(std::span<const std::uint8_t* const> data, std::span<std::uint8_t* const> parity, std::size_t bytes) const;

  /// Rebuilds the missing data shards in place. `shards` holds the k data shards, then the r
  /// parity shards (each `bytes` long; a missing data shard's memory is written); `present` says
  /// which arrived. False (nothing written) when fewer than k are present.
  bool recover(std::span<std::uint8_t* const> shards, const std::vector<bool>& present, std::size_t bytes) const;

 private:
  int k_, r_;
  std::vector<std::uint8_t> matrix_;         ///< (k + r) × k: identity on top, Cauchy rows below
  std::vector<std::uint8_t> encode_tables_;  ///< ISA-L's expanded tables of the parity rows
};

}  // namespace telesphere::link::media
