// SPDX-License-Identifier: MIT
/// @brief Session progress (see session_progress.h).
#include "console/study/session_progress.h"

#include <set>

#include "console/study/trial_order.h"

namespace telesphere::console::study {
namespace {

std::size_t itemsPerMode(const StudyDefinition& study) {
  std::size_t items = 0;
  for (const Questionnaire& q : study.questionnaires) items += q.items.size();
  return items;
}

}  // namespace

std::vector<SessionRecord> sessionsOfStudy(const StudyStore& store, const StudyDefinition& study) {
  std::vector<SessionRecord> sessions;
  for (const SessionRecord& s : store.sessions())
    if (s.study_name == study.name) sessions.push_back(s);
  return sessions;
}

std::optional<SessionRecord> startOrResumeSession(StudyStore& store, const StudyDefinition& study,
                                                  const std::string& participant, std::uint64_t participant_index,
                                                  bool* resumed, std::string* why) {
  std::optional<SessionRecord> record = store.findSession(participant, study.name);
  *resumed = record.has_value();
  if (record) return record;
  const auto id = store.startSession(participant, std::int64_t(participant_index), study,
                                     trialOrder(study, participant_index), why);
  if (!id) return std::nullopt;
  return store.findSession(participant, study.name);
}

SessionProgress sessionProgress(const SessionRecord& session, const StudyDefinition& study,
                                const std::vector<TrialRecord>& trials, const std::vector<AnswerRecord>& answers) {
  std::set<int> finished;
  for (const TrialRecord& t : trials)
    if (t.session_id == session.id && t.outcome != TrialOutcome::kRunning && t.outcome != TrialOutcome::kInterrupted)
      finished.insert(t.order_index);
  SessionProgress p;
  p.trials_finished = finished.size();
  p.trials = session.order.size();
  for (const AnswerRecord& a : answers) p.answers += a.session_id == session.id;
  p.answers_needed = itemsPerMode(study) * session.order.size();
  p.complete = !session.ended_utc.empty();
  return p;
}

std::size_t nextQuestionnaire(const SessionRecord& session, const StudyDefinition& study,
                              const std::vector<AnswerRecord>& answers) {
  const std::size_t items = itemsPerMode(study);
  for (std::size_t i = 0; i < session.order.size(); ++i) {
    std::size_t n = 0;
    for (const AnswerRecord& a : answers) n += a.session_id == session.id && a.mode == session.order[i];
    if (n < items) return i;
  }
  return session.order.size();
}

}  // namespace telesphere::console::study
