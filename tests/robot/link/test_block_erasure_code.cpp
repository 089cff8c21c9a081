// SPDX-License-Identifier: MIT
/// @brief BlockErasureCode (ISA-L's Reed–Solomon): every pattern of up to r lost shards of a small
///        block comes back byte-identical, r + 1 do not; the extremes (k = 1, k + r = 255, r = 0,
///        one-byte shards) and bad arguments.
#include <gtest/gtest.h>

#include <random>

#include "robot/link/media/block_erasure_code.h"

namespace telesphere::link::media {
namespace {

struct Block {
  std::vector<std::vector<std::uint8_t>> shards;  ///< k data, then r parity
};

Block encoded(int k, int r, std::size_t bytes, unsigned seed) {
  std::mt19937 rng(seed);
  Block b;
  b.shards.assign(static_cast<std::size_t>(k + r), std::vector<std::uint8_t>(bytes));
  for (int i = 0; i < k; ++i)
    for (auto& v : b.shards[static_cast<std::size_t>(i)]) v = static_cast<std::uint8_t>(rng());
  std::vector<const std::uint8_t*> data;
  std::vector<std::uint8_t*> parity;
  for (int i = 0; i < k; ++i) data.push_back(b.shards[static_cast<std::size_t>(i)].data());
  for (int j = 0; j < r; ++j) parity.push_back(b.shards[static_cast<std::size_t>(k + j)].data());
  BlockErasureCode(k, r).encode(data, parity, bytes);
  return b;
}

/// Loses the shards whose bit is set in `lost` (the first 32 shards only), recovers, compares.
bool recovers(const Block& original, int k, int r, std::uint32_t lost) {
  Block b = original;
  std::vector<bool> present(static_cast<std::size_t>(k + r));
  std::vector<std::uint8_t*> shards;
  for (int i = 0; i < k + r; ++i) {
    present[static_cast<std::size_t>(i)] = !(i < 32 && (lost >> i & 1));
    if (!present[static_cast<std::size_t>(i)]) std::fill(b.shards[static_cast<std::size_t>(i)].begin(), b.shards[static_cast<std::size_t>(i)].end(), 0xEE);
    shards.push_back(b.shards[static_cast<std::size_t>(i)].data());
  }
  if (!BlockErasureCode(k, r).recover(shards, present, b.shards[0].size())) return false;
  for (int i = 0; i < k; ++i)
    if (b.shards[static_cast<std::size_t>(i)] != original.shards[static_cast<std::size_t>(i)]) return false;
  return true;
}

TEST(BlockErasureCode, AnyRLostShardsComeBackAndRPlusOneDoNot) {
  const int k = 6, r = 3;
  const Block b = encoded(k, r, 1364, 1);
  int patterns = 0;
  for (std::uint32_t lost = 0; lost < (1u << (k + r)); ++lost) {
    const int n = __builtin_popcount(lost);
    if (n <= r) {
      ASSERT_TRUE(recovers(b, k, r, lost)) << "lost pattern " << lost;
      ++patterns;
    } else if (n == r + 1) {
      // With more than r lost, fewer than k shards remain: nothing can be rebuilt.
      ASSERT_FALSE(recovers(b, k, r, lost)) << "lost pattern " << lost;
    }
  }
  EXPECT_EQ(patterns, 1 + 9 + 36 + 84);
}

TEST(BlockErasureCode, TheExtremes) {
  // One data shard and one parity shard: the parity is a copy.
  const Block one = encoded(1, 1, 17, 2);
  EXPECT_EQ(one.shards[1], one.shards[0]);
  EXPECT_TRUE(recovers(one, 1, 1, 0b01));
  // The largest block GF(2⁸) allows, five shards lost among the data.
  const Block big = encoded(250, 5, 64, 3);
  EXPECT_TRUE(recovers(big, 250, 5, 0b11111));
  // One-byte shards; no parity at all (nothing lost: fine; one lost: not).
  const Block tiny = encoded(4, 2, 1, 4);
  EXPECT_TRUE(recovers(tiny, 4, 2, 0b100100));
  const Block none = encoded(3, 0, 8, 5);
  EXPECT_TRUE(recovers(none, 3, 0, 0));
  EXPECT_FALSE(recovers(none, 3, 0, 0b1));
  EXPECT_THROW(BlockErasureCode(0, 1), std::invalid_argument);
  EXPECT_THROW(BlockErasureCode(250, 6), std::invalid_argument);
  EXPECT_THROW(BlockErasureCode(3, -1), std::invalid_argument);
}

}  // namespace
}  // namespace telesphere::link::media
