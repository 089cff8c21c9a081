// SPDX-License-Identifier: MIT
#include "app/bench/impairment/loss_model.h"

#include <cassert>
#include <cmath>

namespace telesphere::bench::impairment {

std::string checkLossOptions(const LossOptions& options) {
  if (!(options.loss_fraction >= 0 && options.loss_fraction < 1))
    return "loss must be a fraction in [0, 1), not " + std::to_string(options.loss_fraction);
  if (!(options.mean_burst_packets >= 1) || !std::isfinite(options.mean_burst_packets))
    return "the mean loss burst must be ≥ 1 packet, not " + std::to_string(options.mean_burst_packets);
  const double b = options.mean_burst_packets, p = options.loss_fraction;
  if (b > 1 && p / (b * (1 - p)) > 1)  // good → bad would have to exceed certainty
    return "a loss of " + std::to_string(p) + " in bursts of " + std::to_string(b) +
           " packets cannot be made: at most b/(b + 1) = " + std::to_string(b / (b + 1));
  return {};
}

LossModel::LossModel(const LossOptions& options) : options_(options), rng_(options.seed) {
  assert(checkLossOptions(options).empty());
  r_ = 1.0 / options_.mean_burst_packets;
  q_ = options_.loss_fraction * r_ / (1.0 - options_.loss_fraction);
}

bool LossModel::nextLost() {
  if (options_.loss_fraction <= 0) return false;
  if (options_.mean_burst_packets <= 1) return u01_(rng_) < options_.loss_fraction;
  // The state for this packet: leave the current one with its transition probability.
  bad_ = bad_ ? !(u01_(rng_) < r_) : u01_(rng_) < q_;
  return bad_;
}

}  // namespace telesphere::bench::impairment
