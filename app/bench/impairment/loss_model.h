// SPDX-License-Identifier: MIT
/// @brief Which packets a path loses, seeded: none, independent (Bernoulli) or in bursts
///        (Gilbert–Elliott with a lossless good state and an all-losing bad state). For bursts,
///        the mean loss rate p and the mean burst length b (packets) give the transition
///        probabilities: bad → good r = 1/b, good → bad q = p·r/(1 − p), so that the stationary
///        share of the bad state is q/(q + r) = p. The same seed loses the same packets.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string>

namespace telesphere::bench::impairment {

struct LossOptions {
  double loss_fraction = 0;    ///< mean share of packets lost, [0, 1)
  double mean_burst_packets = 1;  ///< 1: independent losses; > 1: bursts of this mean length
  std::uint64_t seed = 1;
};

/// Nothing wrong: empty; else what is wrong, for the caller's error message.
std::string checkLossOptions(const LossOptions& options);

class LossModel {
 public:
  /// Options must pass checkLossOptions (asserted in debug builds).
  explicit LossModel(const LossOptions& options = {});

  /// Whether the next packet offered to the path is lost.
  bool nextLost();

  double goodToBad() const { return q_; }
  double badToGood() const { return r_; }

 private:
  LossOptions options_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> u01_{0.0, 1.0};
  double q_ = 0, r_ = 1;
  bool bad_ = false;
};

}  // namespace telesphere::bench::impairment
