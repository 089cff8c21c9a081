// SPDX-License-Identifier: MIT
/// @brief StudyDefinition: parsing, defaults, the questionnaires (see study_definition.h).
#include "console/study/study_definition.h"

#include <nlohmann/json.hpp>
#include <set>

namespace telesphere::console::study {

Questionnaire paperLikert() {
  Questionnaire q{"paper_likert", {}};
  const char* items[][2] = {{"situational_awareness", "Did you maintain situational awareness?"},
                            {"see_objects", "Could you clearly see the objects?"},
                            {"judge_depth", "Could you judge depth correctly?"},
                            {"comfortable", "Was the VR experience comfortable for your eyes?"},
                            {"recognize_objects", "Did you find and recognize the objects?"},
                            {"grasp", "Was it easy to grasp the objects?"},
                            {"fit", "Was it easy to fit the objects together?"}};
  for (const auto& [key, text] : items) q.items.push_back({key, text, 1, 7});
  return q;
}

Questionnaire nasaTlxRaw() {
  Questionnaire q{"nasa_tlx_raw", {}};
  const char* items[][2] = {{"mental", "Mental demand: how mentally demanding was the task?"},
                            {"physical", "Physical demand: how physically demanding was the task?"},
                            {"temporal", "Temporal demand: how hurried or rushed was the pace?"},
                            {"performance", "Performance: how successful were you (0 perfect, 100 failure)?"},
                            {"effort", "Effort: how hard did you have to work?"},
                            {"frustration", "Frustration: how insecure, discouraged, irritated were you?"}};
  for (const auto& [key, text] : items) q.items.push_back({key, text, 0, 100});
  return q;
}

Questionnaire systemUsabilityScale() {
  Questionnaire q{"sus", {}};
  const char* items[] = {"I think that I would like to use this system frequently.",
                         "I found the system unnecessarily complex.",
                         "I thought the system was easy to use.",
                         "I think that I would need the support of a technical person to be able to use this system.",
                         "I found the various functions in this system were well integrated.",
                         "I thought there was too much inconsistency in this system.",
                         "I would imagine that most people would learn to use this system very quickly.",
                         "I found the system very cumbersome to use.",
                         "I felt very confident using the system.",
                         "I needed to learn a lot of things before I could get going with this system."};
  int i = 0;
  for (const char* text : items) q.items.push_back({"q" + std::to_string(++i), text, 1, 5});
  return q;
}

bool isVisualModeName(const std::string& mode) {
  return mode == "full6d" || mode == "orientation3d" || mode == "fixed";
}

std::optional<StudyDefinition> StudyDefinition::parse(const std::string& text, std::string* error) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    *error = std::string("not JSON: ") + e.what();
    return std::nullopt;
  }
  if (!j.is_object()) {
    *error = "a study is a JSON object";
    return std::nullopt;
  }
  StudyDefinition d;
  const std::set<std::string> known = {"name", "modes", "order", "seed", "time_limit_s", "questionnaires"};
  for (const auto& [key, value] : j.items())
    if (!known.count(key)) {
      *error = "unknown key '" + key + "'";
      return std::nullopt;
    }
  try {
    if (j.contains("name")) d.name = j.at("name").get<std::string>();
    if (d.name.empty() || d.name.find_first_of("/\\_ ") != std::string::npos) {
      *error = "name: must be non-empty without '/', '\\\\', '_' or spaces (it goes into file names)";
      return std::nullopt;
    }
    if (j.contains("modes")) d.modes = j.at("modes").get<std::vector<std::string>>();
    std::set<std::string> seen;
    for (const auto& m : d.modes)
      if (!isVisualModeName(m) || !seen.insert(m).second) {
        *error = "modes: '" + m + "' is not one of full6d, orientation3d, fixed, or comes twice";
        return std::nullopt;
      }
    if (d.modes.empty()) {
      *error = "modes: at least one";
      return std::nullopt;
    }
    if (j.contains("order")) {
      const auto order = j.at("order").get<std::string>();
      if (order == "counterbalanced") d.order = OrderScheme::kCounterbalanced;
      else if (order == "seeded_random") d.order = OrderScheme::kSeededRandom;
      else {
        *error = "order: 'counterbalanced' or 'seeded_random', not '" + order + "'";
        return std::nullopt;
      }
    }
    if (j.contains("seed")) d.seed = j.at("seed").get<std::uint64_t>();
    if (j.contains("time_limit_s")) d.time_limit_s = j.at("time_limit_s").get<double>();
    if (!(d.time_limit_s > 0 && d.time_limit_s <= 24 * 3600)) {
      *error = "time_limit_s: must be in (0, 86400]";
      return std::nullopt;
    }
    bool likert = true, tlx = false, sus = false;
    if (j.contains("questionnaires")) {
      const auto& q = j.at("questionnaires");
      for (const auto& [key, value] : q.items())
        if (key != "paper_likert" && key != "nasa_tlx" && key != "sus") {
          *error = "questionnaires: unknown '" + key + "'";
          return std::nullopt;
        }
      likert = q.value("paper_likert", true);
      tlx = q.value("nasa_tlx", false);
      sus = q.value("sus", false);
    }
    if (likert) d.questionnaires.push_back(paperLikert());
    if (tlx) d.questionnaires.push_back(nasaTlxRaw());
    if (sus) d.questionnaires.push_back(systemUsabilityScale());
  } catch (const nlohmann::json::exception& e) {
    *error = std::string("wrong type: ") + e.what();
    return std::nullopt;
  }
  return d;
}

std::string StudyDefinition::toJson() const {
  nlohmann::json q = nlohmann::json::object();
  for (const auto& questionnaire : questionnaires) {
    if (questionnaire.instrument == "paper_likert") q["paper_likert"] = true;
    if (questionnaire.instrument == "nasa_tlx_raw") q["nasa_tlx"] = true;
    if (questionnaire.instrument == "sus") q["sus"] = true;
  }
  if (!q.contains("paper_likert")) q["paper_likert"] = false;
  const nlohmann::json j = {{"name", name},
                            {"modes", modes},
                            {"order", order == OrderScheme::kCounterbalanced ? "counterbalanced" : "seeded_random"},
                            {"seed", seed},
                            {"time_limit_s", time_limit_s},
                            {"questionnaires", q}};
  return j.dump();
}

}  // namespace telesphere::console::study
