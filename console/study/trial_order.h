// SPDX-License-Identifier: MIT
/// @brief The order in which a participant tries the study's modes. Counterbalanced: all n!
///        permutations in lexicographic order, participant i (0-based) gets permutation i mod n!,
///        so every block of n! participants sees each order once and each mode equally often in
///        each position (3 modes: 6 orders). Seeded random: a permutation drawn from (seed,
///        participant index), reproducible from what the session stores.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "console/study/study_definition.h"

namespace telesphere::console::study {

/// The modes of `study` in the order participant `participant_index` (0-based) tries them.
std::vector<std::string> trialOrder(const StudyDefinition& study, std::uint64_t participant_index);

}  // namespace telesphere::console::study
