// SPDX-License-Identifier: MIT
/// @brief trialOrder (see trial_order.h).
#include "console/study/trial_order.h"

#include <algorithm>
#include <random>

namespace telesphere::console::study {

std::vector<std::string> trialOrder(const StudyDefinition& study, std::uint64_t participant_index) {
  std::vector<std::string> order = study.modes;
  if (study.order == OrderScheme::kSeededRandom) {
    // splitmix-style mixing of seed and index, then a Fisher–Yates shuffle with our own draws
    // (std::shuffle's use of the engine is not specified, so results could differ by library).
    std::uint64_t state = study.seed * 0x9E3779B97F4A7C15ULL + participant_index;
    const auto next = [&state] {
      std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
      return z ^ (z >> 31);
    };
    for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[next() % i]);
    return order;
  }
  std::vector<std::size_t> index(order.size());
  for (std::size_t i = 0; i < index.size(); ++i) index[i] = i;
  std::uint64_t permutations = 1;
  for (std::size_t i = 2; i <= index.size(); ++i) permutations *= i;
  for (std::uint64_t k = 0; k < participant_index % permutations; ++k) std::next_permutation(index.begin(), index.end());
  std::vector<std::string> out;
  for (std::size_t i : index) out.push_back(order[i]);
  return out;
}

}  // namespace telesphere::console::study
