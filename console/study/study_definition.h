// SPDX-License-Identifier: MIT
/// @brief A user study as the administrator writes it (JSON, paper §IV-B): the visual modes each
///        participant tries, how their order is assigned, the time limit of a trial and the
///        questionnaires asked after all trials. Defaults are the paper's study: full 6D, 3D
///        orientation and fixed perspective, fully counterbalanced, 300 s, the seven Likert 1–7
///        questions per mode.
///
/// File (every key optional):
///   { "name": "peg-in-hole", "modes": ["full6d", "orientation3d", "fixed"],
///     "order": "counterbalanced" | "seeded_random", "seed": 1, "time_limit_s": 300,
///     "questionnaires": { "paper_likert": true, "nasa_tlx": false, "sus": false } }
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::console::study {

enum class OrderScheme { kCounterbalanced, kSeededRandom };

/// One questionnaire item: its key (stored with each answer), its text and scale.
struct QuestionnaireItem {
  std::string key;
  std::string text;
  int min = 1, max = 7;
};

/// A questionnaire asked once per mode after all trials ("instrument" in the answers).
struct Questionnaire {
  std::string instrument;  ///< "paper_likert", "nasa_tlx_raw", "sus"
  std::vector<QuestionnaireItem> items;
};

struct StudyDefinition {
  std::string name = "study";
  std::vector<std::string> modes = {"full6d", "orientation3d", "fixed"};  ///< link visual modes
  OrderScheme order = OrderScheme::kCounterbalanced;
  std::uint64_t seed = 1;
  double time_limit_s = 300.0;
  std::vector<Questionnaire> questionnaires;  ///< filled from the file's switches

  /// Parses the JSON text; nothing, with the reason (naming the key), on bad input.
  static std::optional<StudyDefinition> parse(const std::string& json, std::string* error);
  /// The definition as JSON (what a session stores).
  std::string toJson() const;
};

/// The paper's seven questions (its user-study figure), 1–7.
Questionnaire paperLikert();
/// Raw NASA-TLX: six subscales, 0–100.
Questionnaire nasaTlxRaw();
/// System Usability Scale: ten items, 1–5.
Questionnaire systemUsabilityScale();

/// The visual modes a study may use (the link's names).
bool isVisualModeName(const std::string& mode);

}  // namespace telesphere::console::study
