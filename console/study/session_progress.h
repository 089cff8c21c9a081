// SPDX-License-Identifier: MIT
/// @brief Where each participant's session of a study stands, as the administrator resumes it:
///        the participant's session found or started with its counterbalanced order, how many
///        trials are finished and questionnaire answers given, and which mode's questionnaire
///        comes next. Qt-free, from the store's records; the Study panel only shows it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "console/study/study_definition.h"
#include "console/study/study_store.h"

namespace telesphere::console::study {

/// The sessions of `study` in `store` (by its name), in the store's order.
std::vector<SessionRecord> sessionsOfStudy(const StudyStore& store, const StudyDefinition& study);

/// The participant's session of `study`, resumed (*resumed true) or started with the trial order
/// of `participant_index` (trialOrder); nullopt with the store's reason in *why.
std::optional<SessionRecord> startOrResumeSession(StudyStore& store, const StudyDefinition& study,
                                                  const std::string& participant, std::uint64_t participant_index,
                                                  bool* resumed, std::string* why);

/// How far a session is.
struct SessionProgress {
  std::size_t trials_finished = 0;  ///< order positions with an outcome (not running, not interrupted)
  std::size_t trials = 0;           ///< the session's order
  std::size_t answers = 0;          ///< questionnaire answers given
  std::size_t answers_needed = 0;   ///< every item of every questionnaire, once per mode
  bool complete = false;            ///< the session has ended
};

/// `session`'s progress from all trials and answers of the store.
SessionProgress sessionProgress(const SessionRecord& session, const StudyDefinition& study,
                                const std::vector<TrialRecord>& trials, const std::vector<AnswerRecord>& answers);

/// The position in `session.order` of the first mode whose questionnaires are not all answered;
/// `session.order.size()` when all are (or the study asks none).
std::size_t nextQuestionnaire(const SessionRecord& session, const StudyDefinition& study,
                              const std::vector<AnswerRecord>& answers);

}  // namespace telesphere::console::study
