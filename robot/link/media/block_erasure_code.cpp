// SPDX-License-Identifier: MIT
/// @brief BlockErasureCode over ISA-L's ec_encode_data, gf_gen_cauchy1_matrix, gf_invert_matrix.
#include "robot/link/media/block_erasure_code.h"

#include <isa-l/erasure_code.h>

#include <stdexcept>
#include <string>

namespace telesphere::link::media {

BlockErasureCode::BlockErasureCode(int k, int r) : k_(k), r_(r) {
  if (k < 1 || r < 0 || k + r > 255)
    throw std::invalid_argument("erasure code: k = " + std::to_string(k) + ", r = " + std::to_string(r) +
                                " (need 1 <= k, 0 <= r, k + r <= 255)");
  matrix_.resize(static_cast<std::size_t>(k + r) * static_cast<std::size_t>(k));
  gf_gen_cauchy1_matrix(matrix_.data(), k + r, k);
  if (r > 0) {
    encode_tables_.resize(static_cast<std::size_t>(32) * k * r);
    ec_init_tables(k, r, matrix_.data() + static_cast<std::size_t>(k) * k, encode_tables_.data());
  }
}

void BlockErasureCode::encode(std::span<const std::uint8_t* const> data, std::span<std::uint8_t* const> parity,
                              std::size_t bytes) const {
  if (r_ == 0 || bytes == 0) return;
  if (static_cast<int>(data.size()) != k_ || static_cast<int>(parity.size()) != r_)
    throw std::invalid_argument("erasure code: wrong shard counts");
  // ISA-L takes non-const pointers; it only reads the data shards.
  std::vector<std::uint8_t*> in(data.size());
  for (std::size_t i = 0; i < data.size(); ++i) in[i] = const_cast<std::uint8_t*>(data[i]);
  std::vector<std::uint8_t*> out(parity.begin(), parity.end());
  ec_encode_data(static_cast<int>(bytes), k_, r_, const_cast<std::uint8_t*>(encode_tables_.data()), in.data(),
                 out.data());
}

bool BlockErasureCode::recover(std::span<std::uint8_t* const> shards, const std::vector<bool>& present,
                               std::size_t bytes) const {
  const auto n = static_cast<std::size_t>(k_ + r_);
  if (shards.size() != n || present.size() != n) throw std::invalid_argument("erasure code: wrong shard counts");
  std::vector<int> missing;
  for (int i = 0; i < k_; ++i)
    if (!present[static_cast<std::size_t>(i)]) missing.push_back(i);
  if (missing.empty()) return true;
  // The first k shards that arrived, and the rows of the generator matrix that made them.
  std::vector<int> rows;
  for (std::size_t i = 0; i < n && static_cast<int>(rows.size()) < k_; ++i)
    if (present[i]) rows.push_back(static_cast<int>(i));
  if (static_cast<int>(rows.size()) < k_) return false;
  const auto k = static_cast<std::size_t>(k_);
  std::vector<std::uint8_t> sub(k * k), inverse(k * k);
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = 0; j < k; ++j) sub[i * k + j] = matrix_[static_cast<std::size_t>(rows[i]) * k + j];
  if (gf_invert_matrix(sub.data(), inverse.data(), k_) != 0) return false;  // cannot happen for Cauchy
  // Each missing data shard is its row of the inverse applied to the shards that arrived.
  std::vector<std::uint8_t> decode(missing.size() * k);
  for (std::size_t m = 0; m < missing.size(); ++m)
    for (std::size_t j = 0; j < k; ++j) decode[m * k + j] = inverse[static_cast<std::size_t>(missing[m]) * k + j];
  std::vector<std::uint8_t> tables(32 * k * missing.size());
  ec_init_tables(k_, static_cast<int>(missing.size()), decode.data(), tables.data());
  std::vector<std::uint8_t*> in(k), out(missing.size());
  for (std::size_t i = 0; i < k; ++i) in[i] = shards[static_cast<std::size_t>(rows[i])];
  for (std::size_t m = 0; m < missing.size(); ++m) out[m] = shards[static_cast<std::size_t>(missing[m])];
  ec_encode_data(static_cast<int>(bytes), k_, static_cast<int>(missing.size()), tables.data(), in.data(), out.data());
  return true;
}

}  // namespace telesphere::link::media
