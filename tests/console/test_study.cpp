// SPDX-License-Identifier: MIT
/// @brief The study administrator's logic against real SQLite (QtSql): the study file, balanced
///        trial orders, the store's events and their rules, nothing lost when the console is
///        killed (SIGKILL) during a trial or a questionnaire, the schema version, tidy CSV round
///        trips, and the summary against an independent computation on seeded data; the paper's
///        own questionnaire answers reproduce its figure (written to console/docs).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <QApplication>
#include <QSqlDatabase>
#include <QSqlQuery>
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <iterator>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include "console/study/session_progress.h"
#include "console/study/study_report.h"
#include "console/study/study_store.h"
#include "console/study/study_summary.h"
#include "console/study/tidy_csv.h"
#include "console/study/trial_order.h"
#include "console/study/trial_runner.h"
#include "console/study/trial_telemetry.h"
#include "console/study/trial_telemetry_buffer.h"
#include "console/study/trial_workflow.h"
#include "robot/link/proto_enums.h"
#include "robot/link/telesphere_link.pb.h"
#include "robot/link/visual_mode.h"

namespace telesphere::console::study {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("telesphere_study_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

StudyDefinition paperStudy() {
  std::string error;
  auto d = StudyDefinition::parse("{}", &error);
  EXPECT_TRUE(d) << error;
  return *d;
}

TEST(StudyDefinition, DefaultsAreThePapersStudyAndBadFilesNameTheKey) {
  const StudyDefinition d = paperStudy();
  EXPECT_EQ(d.modes, (std::vector<std::string>{"full6d", "orientation3d", "fixed"}));
  EXPECT_EQ(d.time_limit_s, 300.0);
  ASSERT_EQ(d.questionnaires.size(), 1u);
  EXPECT_EQ(d.questionnaires[0].items.size(), 7u);
  EXPECT_EQ(d.questionnaires[0].items[2].text, "Could you judge depth correctly?");
  std::string error;
  const auto full = StudyDefinition::parse(
      R"({"name":"pilot","modes":["fixed","full6d"],"order":"seeded_random","seed":7,"time_limit_s":120,
          "questionnaires":{"paper_likert":true,"nasa_tlx":true,"sus":true}})", &error);
  ASSERT_TRUE(full) << error;
  EXPECT_EQ(full->questionnaires.size(), 3u);
  EXPECT_EQ(StudyDefinition::parse(full->toJson(), &error)->toJson(), full->toJson());
  for (const auto& [text, key] : std::vector<std::pair<std::string, std::string>>{
           {R"({"mode":["full6d"]})", "unknown key 'mode'"},
           {R"({"modes":["full6d","6d"]})", "modes"},
           {R"({"modes":["full6d","full6d"]})", "comes twice"},
           {R"({"order":"latin"})", "order"},
           {R"({"time_limit_s":-1})", "time_limit_s"},
           {R"({"name":"my study"})", "name"},
           {R"({"questionnaires":{"tlx":true}})", "questionnaires"},
           {"[1,2]", "object"},
           {"{", "not JSON"}}) {
    EXPECT_FALSE(StudyDefinition::parse(text, &error)) << text;
    EXPECT_NE(error.find(key), std::string::npos) << text << " → " << error;
  }
}

TEST(TrialOrder, CounterbalancingOverTwelveParticipantsIsBalanced) {
  const StudyDefinition d = paperStudy();
  std::map<std::vector<std::string>, int> orders;
  std::map<std::pair<int, std::string>, int> position;
  for (int p = 0; p < 12; ++p) {
    const auto order = trialOrder(d, static_cast<std::uint64_t>(p));
    ASSERT_EQ(order.size(), 3u);
    ++orders[order];
    for (int i = 0; i < 3; ++i) ++position[{i, order[static_cast<std::size_t>(i)]}];
  }
  EXPECT_EQ(orders.size(), 6u);
  for (const auto& [order, n] : orders) EXPECT_EQ(n, 2);
  for (const auto& [key, n] : position) EXPECT_EQ(n, 4) << key.first << " " << key.second;
  // Seeded random: reproducible from (seed, index), a permutation, not always the same.
  StudyDefinition r = d;
  r.order = OrderScheme::kSeededRandom;
  r.seed = 42;
  std::set<std::vector<std::string>> seen;
  for (int p = 0; p < 12; ++p) {
    const auto a = trialOrder(r, static_cast<std::uint64_t>(p));
    EXPECT_EQ(a, trialOrder(r, static_cast<std::uint64_t>(p)));
    auto sorted = a;
    std::sort(sorted.begin(), sorted.end());
    auto modes = d.modes;
    std::sort(modes.begin(), modes.end());
    EXPECT_EQ(sorted, modes);
    seen.insert(a);
  }
  EXPECT_GT(seen.size(), 2u);
}

TEST(StudyStore, EventsAreStoredAndTheirRulesHold) {
  const fs::path dir = freshDir("events");
  std::string error;
  auto store = StudyStore::open((dir / "s.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  const StudyDefinition d = paperStudy();
  const auto session = store->startSession("P01", 0, d, trialOrder(d, 0), &error);
  ASSERT_TRUE(session) << error;
  EXPECT_FALSE(store->startSession("P01", 1, d, trialOrder(d, 1), &error));
  EXPECT_NE(error.find("already"), std::string::npos);
  EXPECT_FALSE(store->startSession("P 02", 1, d, trialOrder(d, 1), &error));
  const auto trial = store->startTrial(*session, 0, "full6d", 300, &error);
  ASSERT_TRUE(trial) << error;
  ASSERT_TRUE(store->addAttempt(*trial, &error)) << error;
  ASSERT_TRUE(store->addAttempt(*trial, &error)) << error;
  ASSERT_TRUE(store->setNotes(*trial, "peg slipped, \"twice\", reset", &error)) << error;
  ASSERT_TRUE(store->addRecording(*trial, "/data/rec/P01-full6d-trial1.mcap", &error)) << error;
  EXPECT_FALSE(store->addRecording(*trial + 100, "x.mcap", &error));  // no such trial
  EXPECT_FALSE(store->endTrial(*trial, TrialOutcome::kAbort, 10, "", &error));  // a reason is required
  ASSERT_TRUE(store->endTrial(*trial, TrialOutcome::kSuccess, 71.25, "", &error)) << error;
  EXPECT_FALSE(store->addAttempt(*trial, &error));  // not running any more
  EXPECT_FALSE(store->endTrial(*trial, TrialOutcome::kFail, 1, "", &error));
  ASSERT_TRUE(store->saveAnswer(*session, "full6d", "paper_likert", "grasp", 5, &error)) << error;
  ASSERT_TRUE(store->saveAnswer(*session, "full6d", "paper_likert", "grasp", 6, &error)) << error;  // corrected
  const auto trials = store->trials();
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].participant, "P01");
  EXPECT_EQ(trials[0].attempts, 2);
  EXPECT_EQ(trials[0].outcome, TrialOutcome::kSuccess);
  EXPECT_EQ(trials[0].duration_s, 71.25);
  EXPECT_EQ(trials[0].notes, "peg slipped, \"twice\", reset");
  EXPECT_EQ(trials[0].recording, "/data/rec/P01-full6d-trial1.mcap");
  const auto answers = store->answers();
  ASSERT_EQ(answers.size(), 1u);
  EXPECT_EQ(answers[0].value, 6.0);
  const auto s = store->findSession("P01", d.name);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->order, trialOrder(d, 0));
  EXPECT_EQ(s->order_scheme, "counterbalanced");
  store.reset();
  fs::remove_all(dir);
}

TEST(SessionProgress, SessionsStartedOrResumedTheirProgressAndTheNextQuestionnaire) {
  const fs::path dir = freshDir("progress");
  std::string error;
  auto store = StudyStore::open((dir / "s.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  const StudyDefinition d = paperStudy();
  bool resumed = true;
  const auto s = startOrResumeSession(*store, d, "P01", 2, &resumed, &error);
  ASSERT_TRUE(s) << error;
  EXPECT_FALSE(resumed);
  EXPECT_EQ(s->order, trialOrder(d, 2));
  const auto again = startOrResumeSession(*store, d, "P01", 5, &resumed, &error);  // the index is the first one's
  ASSERT_TRUE(again) << error;
  EXPECT_TRUE(resumed);
  EXPECT_EQ(again->id, s->id);
  EXPECT_EQ(again->order, trialOrder(d, 2));
  EXPECT_FALSE(startOrResumeSession(*store, d, "P 02", 3, &resumed, &error));  // the store refuses the id
  EXPECT_FALSE(error.empty());
  EXPECT_EQ(sessionsOfStudy(*store, d).size(), 1u);
  StudyDefinition other = d;
  other.name = "another-study";
  EXPECT_TRUE(sessionsOfStudy(*store, other).empty());

  // Trial 1 ends, trial 2 still runs (not finished); every item of the first mode answered.
  const auto t1 = store->startTrial(s->id, 0, s->order[0], 300, &error);
  ASSERT_TRUE(t1) << error;
  ASSERT_TRUE(store->endTrial(*t1, TrialOutcome::kSuccess, 50, "", &error)) << error;
  ASSERT_TRUE(store->startTrial(s->id, 1, s->order[1], 300, &error)) << error;
  std::size_t items = 0;
  for (const Questionnaire& q : d.questionnaires) {
    items += q.items.size();
    for (const QuestionnaireItem& item : q.items)
      ASSERT_TRUE(store->saveAnswer(s->id, s->order[0], q.instrument, item.key, 4, &error)) << error;
  }
  ASSERT_GT(items, 0u);
  ASSERT_TRUE(store->saveAnswer(s->id, s->order[1], d.questionnaires[0].instrument, d.questionnaires[0].items[0].key, 4,
                                &error))
      << error;
  const SessionProgress p = sessionProgress(*s, d, store->trials(), store->answers());
  EXPECT_EQ(p.trials_finished, 1u);
  EXPECT_EQ(p.trials, 3u);
  EXPECT_EQ(p.answers, items + 1);
  EXPECT_EQ(p.answers_needed, 3 * items);
  EXPECT_FALSE(p.complete);
  EXPECT_EQ(nextQuestionnaire(*s, d, store->answers()), 1u);  // the second mode's page is not complete
  StudyDefinition none = d;
  none.questionnaires.clear();
  EXPECT_EQ(nextQuestionnaire(*s, none, store->answers()), 3u);  // nothing to ask: all done
  store.reset();
  fs::remove_all(dir);
}

TEST(TrialTelemetryBuffer, KeptUntilDueThenCommittedWithItsTrial) {
  const fs::path dir = freshDir("telemetry_buffer");
  std::string error;
  auto store = StudyStore::open((dir / "s.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  const StudyDefinition d = paperStudy();
  const auto session = store->startSession("P01", 0, d, trialOrder(d, 0), &error);
  ASSERT_TRUE(session) << error;
  const auto trial = store->startTrial(*session, 0, "full6d", 300, &error);
  ASSERT_TRUE(trial) << error;
  constexpr std::int64_t kS = 1'000'000'000;
  TrialTelemetryBuffer buffer;
  buffer.add({std::nullopt, "before any trial"});
  EXPECT_TRUE(buffer.flush(*store, 0, &error));  // no trial yet: nothing stored
  buffer.start(*trial, 10 * kS);                   // and the buffer emptied
  EXPECT_FALSE(buffer.due(10 * kS + kS / 2, kS));
  EXPECT_TRUE(buffer.due(11 * kS, kS));
  buffer.add({std::int64_t{42}, "first"});
  buffer.add({std::nullopt, "second"});
  EXPECT_TRUE(buffer.flush(*store, 11 * kS, &error)) << error;
  EXPECT_FALSE(buffer.due(11 * kS + kS / 2, kS));
  EXPECT_TRUE(buffer.flush(*store, 12 * kS, &error));  // nothing new: the period still counts from 11 s
  EXPECT_TRUE(buffer.due(12 * kS, kS));
  const auto stored = store->telemetry(*trial);
  ASSERT_EQ(stored.size(), 2u);
  EXPECT_EQ(stored[0].envelope, "first");
  EXPECT_EQ(stored[0].robot_to_utc_ns, std::optional<std::int64_t>(42));
  EXPECT_EQ(stored[1].envelope, "second");
  store.reset();
  fs::remove_all(dir);
}

/// Runs the crash writer; true when it died of SIGKILL.
bool runCrashWriter(const fs::path& db, const std::string& participant, int attempts, int answers) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string exe = std::string(TELESPHERE_BINARY_DIR) + "/tests/study_crash_writer";
    const std::string a = std::to_string(attempts), b = std::to_string(answers);
    ::execl(exe.c_str(), exe.c_str(), db.c_str(), participant.c_str(), a.c_str(), b.c_str(), nullptr);
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

TEST(StudyStore, KilledDuringATrialOrAQuestionnaireLosesNothing) {
  const fs::path dir = freshDir("crash");
  const fs::path db = dir / "s.sqlite";
  // Killed during a trial after 5 attempts.
  ASSERT_TRUE(runCrashWriter(db, "P01", 5, 0));
  {
    std::string error;
    auto store = StudyStore::open(db.string(), &error);
    ASSERT_TRUE(store) << error;
    ASSERT_EQ(store->interruptedOnOpen().size(), 1u);
    const auto trials = store->trials();
    ASSERT_EQ(trials.size(), 1u);
    EXPECT_EQ(trials[0].attempts, 5);
    EXPECT_EQ(trials[0].outcome, TrialOutcome::kInterrupted);
    EXPECT_FALSE(trials[0].ended_utc.empty());
  }
  // Killed during the questionnaire after 4 of 7 answers (another participant).
  ASSERT_TRUE(runCrashWriter(db, "P02", 1, 4));
  std::string error;
  auto store = StudyStore::open(db.string(), &error);
  ASSERT_TRUE(store) << error;
  EXPECT_TRUE(store->interruptedOnOpen().empty());  // P02's trial had ended
  int p02 = 0;
  for (const auto& a : store->answers()) p02 += a.participant == "P02";
  EXPECT_EQ(p02, 4);
  const auto trials = store->trials();
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[1].outcome, TrialOutcome::kSuccess);
  EXPECT_EQ(trials[1].duration_s, 42.5);
  store.reset();
  fs::remove_all(dir);
}

TEST(StudyStore, ADatabaseFromANewerBuildIsRefused) {
  const fs::path dir = freshDir("schema");
  const fs::path db = dir / "s.sqlite";
  std::string error;
  {
    auto store = StudyStore::open(db.string(), &error);
    ASSERT_TRUE(store) << error;
  }
  {
    QSqlDatabase raw = QSqlDatabase::addDatabase("QSQLITE", "raw");
    raw.setDatabaseName(QString::fromStdString(db.string()));
    ASSERT_TRUE(raw.open());
    QSqlQuery q(raw);
    ASSERT_TRUE(q.exec("PRAGMA user_version"));
    ASSERT_TRUE(q.next());
    EXPECT_EQ(q.value(0).toInt(), StudyStore::kSchemaVersion);
    ASSERT_TRUE(q.exec("PRAGMA user_version=99"));
    raw.close();
  }
  QSqlDatabase::removeDatabase("raw");
  EXPECT_FALSE(StudyStore::open(db.string(), &error));
  EXPECT_NE(error.find("newer"), std::string::npos) << error;
  fs::remove_all(dir);
}

TEST(StudyStore, ASchemaOneDatabaseIsMigratedWithItsDataKept) {
  const fs::path dir = freshDir("migrate");
  const fs::path db = dir / "v1.sqlite";
  {  // what the first build wrote: schema 1, one session, one finished trial
    QSqlDatabase raw = QSqlDatabase::addDatabase("QSQLITE", "v1");
    raw.setDatabaseName(QString::fromStdString(db.string()));
    ASSERT_TRUE(raw.open());
    QSqlQuery q(raw);
    for (const char* sql :
         {"CREATE TABLE sessions(id INTEGER PRIMARY KEY, participant TEXT NOT NULL, participant_index INTEGER NOT NULL,"
          " study_name TEXT NOT NULL, study_json TEXT NOT NULL, order_json TEXT NOT NULL, order_scheme TEXT NOT NULL,"
          " seed INTEGER NOT NULL, started_utc TEXT NOT NULL, ended_utc TEXT, UNIQUE(participant, study_name))",
          "CREATE TABLE trials(id INTEGER PRIMARY KEY, session_id INTEGER NOT NULL REFERENCES sessions(id),"
          " order_index INTEGER NOT NULL, mode TEXT NOT NULL, started_utc TEXT NOT NULL, ended_utc TEXT,"
          " duration_s REAL, outcome TEXT NOT NULL, attempts INTEGER NOT NULL DEFAULT 0, time_limit_s REAL NOT NULL,"
          " abort_reason TEXT NOT NULL DEFAULT '', notes TEXT NOT NULL DEFAULT '')",
          "CREATE TABLE answers(id INTEGER PRIMARY KEY, session_id INTEGER NOT NULL REFERENCES sessions(id),"
          " mode TEXT NOT NULL, instrument TEXT NOT NULL, item TEXT NOT NULL, value REAL NOT NULL,"
          " answered_utc TEXT NOT NULL, UNIQUE(session_id, mode, instrument, item))",
          "CREATE TABLE events(id INTEGER PRIMARY KEY, at_utc TEXT NOT NULL, session_id INTEGER, trial_id INTEGER,"
          " kind TEXT NOT NULL, detail TEXT NOT NULL DEFAULT '')",
          "INSERT INTO sessions VALUES(1, 'P01', 0, 'study', '{}', '[\"full6d\"]', 'counterbalanced', 1,"
          " '2026-11-01T10:00:00.000Z', NULL)",
          "INSERT INTO trials VALUES(1, 1, 0, 'full6d', '2026-11-01T10:01:00.000Z', '2026-11-01T10:02:00.000Z', 60.0,"
          " 'success', 3, 300, '', 'kept')",
          "PRAGMA user_version=1"})
      ASSERT_TRUE(q.exec(sql)) << sql;
    raw.close();
  }
  QSqlDatabase::removeDatabase("v1");
  std::string error;
  auto store = StudyStore::open(db.string(), &error);
  ASSERT_TRUE(store) << error;
  const auto trials = store->trials();
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].notes, "kept");
  EXPECT_EQ(trials[0].attempts, 3);
  EXPECT_TRUE(store->telemetry(1).empty());
  EXPECT_TRUE(store->addTelemetry(1, {{std::int64_t{5}, "bytes"}}, &error)) << error;  // the v2 table exists
  ASSERT_EQ(store->telemetry(1).size(), 1u);
  EXPECT_EQ(*store->telemetry(1)[0].robot_to_utc_ns, 5);
  EXPECT_EQ(store->telemetry(1)[0].envelope, "bytes");
  EXPECT_EQ(trials[0].recording, "");  // v3: the column exists, empty for old trials
  EXPECT_TRUE(store->addRecording(1, "P01-full6d-trial1.mcap", &error)) << error;
  EXPECT_EQ(store->trials()[0].recording, "P01-full6d-trial1.mcap");
  // v4: the database has an id of its own, and a trial says why it is not wholly recorded.
  EXPECT_EQ(store->uid().size(), 8u);
  EXPECT_TRUE(store->addRecording(1, "P01-full6d-trial1-part2.mcap", &error)) << error;
  EXPECT_TRUE(store->addRecordingNote(1, "the robot restarted at 12.3 s", &error)) << error;
  EXPECT_EQ(store->trials()[0].recording, "P01-full6d-trial1.mcap; P01-full6d-trial1-part2.mcap");
  EXPECT_EQ(store->trials()[0].recording_note, "the robot restarted at 12.3 s");
  store.reset();
  fs::remove_all(dir);
}

// One writer per study database (issue #30): a second opener is refused with who holds it, and
// never touches the trial that runs there; a report reads a snapshot and changes nothing; once
// the writer is gone (killed), the next writer takes over and ends its trial as interrupted.
TEST(StudyStore, OneWriterAtATimeAndReportsReadASnapshotThatChangesNothing) {
  const fs::path dir = freshDir("writer");
  const fs::path db = dir / "s.sqlite";
  std::string error;
  auto writer = StudyStore::open(db.string(), &error);
  ASSERT_TRUE(writer) << error;
  const StudyDefinition d = paperStudy();
  const auto session = writer->startSession("P01", 0, d, trialOrder(d, 0), &error);
  ASSERT_TRUE(session) << error;
  const auto done = writer->startTrial(*session, 0, "full6d", 300, &error);
  ASSERT_TRUE(done && writer->endTrial(*done, TrialOutcome::kSuccess, 30, "", &error)) << error;
  const auto running = writer->startTrial(*session, 1, "fixed", 300, &error);
  ASSERT_TRUE(running) << error;

  // A second writer in this process, and one in another process: refused, naming the holder.
  EXPECT_FALSE(StudyStore::open(db.string(), &error));
  EXPECT_NE(error.find("is open in "), std::string::npos) << error;
  EXPECT_NE(error.find("(pid " + std::to_string(getpid()) + " on "), std::string::npos) << error;
  const std::string console = std::string(TELESPHERE_BINARY_DIR) + "/bin/telesphere-console";
  {
    std::ofstream trials(dir / "more.csv");
    trials << "participant,order_index,mode,duration_s,outcome,attempts,time_limit_s\nP09,0,full6d,50,success,1,300\n";
  }
  const std::string import_out = (dir / "import.txt").string();
  const int import_rc = std::system((console + " study import --db " + db.string() + " --trials " +
                                     (dir / "more.csv").string() + " > " + import_out + " 2>&1").c_str());
  std::ifstream import_log(import_out);
  const std::string import_text((std::istreambuf_iterator<char>(import_log)), std::istreambuf_iterator<char>());
  EXPECT_NE(import_rc, 0) << import_text;
  EXPECT_NE(import_text.find("is open in "), std::string::npos) << import_text;

  // A report in another process meanwhile: the running trial listed as running, not counted,
  // and nothing in the database changed.
  const auto events_before = writer->trials();
  const std::string report_out = (dir / "report.txt").string();
  const int report_rc = std::system((console + " study report --db " + db.string() + " --out " +
                                     (dir / "report").string() + " > " + report_out + " 2>&1").c_str());
  std::ifstream report_log(report_out);
  const std::string report_text((std::istreambuf_iterator<char>(report_log)), std::istreambuf_iterator<char>());
  EXPECT_EQ(report_rc, 0) << report_text;
  EXPECT_NE(report_text.find("is running: listed as running, not counted"), std::string::npos) << report_text;
  const auto after = writer->trials();
  ASSERT_EQ(after.size(), 2u);
  EXPECT_EQ(after[1].outcome, TrialOutcome::kRunning);
  EXPECT_TRUE(writer->addAttempt(*running, &error)) << "the trial still runs: " << error;
  // The snapshot in this process too.
  {
    auto snapshot = StudyStore::openSnapshot(db.string(), &error);
    ASSERT_TRUE(snapshot) << error;
    ASSERT_EQ(snapshot->trials().size(), 2u);
    EXPECT_EQ(snapshot->trials()[1].outcome, TrialOutcome::kRunning);
    EXPECT_EQ(snapshot->trials()[1].attempts, 1);
    EXPECT_EQ(snapshot->uid(), writer->uid());
  }
  EXPECT_TRUE(writer->endTrial(*running, TrialOutcome::kFail, 200, "", &error)) << error;
  writer.reset();

  // A writer killed while a trial runs: the next one takes over and ends it as interrupted.
  ASSERT_TRUE(runCrashWriter(db, "P02", 2, 0));
  auto next = StudyStore::open(db.string(), &error);
  ASSERT_TRUE(next) << error;
  ASSERT_EQ(next->interruptedOnOpen().size(), 1u);
  EXPECT_EQ(next->interruptedOnOpen()[0].participant, "P02");
  next.reset();
  // Two databases: two ids (recording names stay unique across them).
  auto other = StudyStore::open((dir / "other.sqlite").string(), &error);
  ASSERT_TRUE(other) << error;
  auto again = StudyStore::open(db.string(), &error);
  ASSERT_TRUE(again) << error;
  EXPECT_NE(other->uid(), again->uid());
  other.reset();
  again.reset();
  fs::remove_all(dir);
}

TEST(TrialTelemetry, StampsMapToSecondsSinceTheTrialStartedOnOneClock) {
  // The trial started at UTC 1000 s. The robot clock is UTC − 400 s; the XR clock is the robot's
  // + 7 s. A head tick at robot 601.5 s and an XR frame displayed at XR 609 s (robot 602 s) fall
  // 1.5 s and 2 s into the trial; the frame's image was captured at robot 601.96 s (40 ms).
  const std::int64_t s = 1'000'000'000;
  const std::int64_t start_utc = 1000 * s, robot_to_utc = 400 * s, robot_to_xr = 7 * s;
  link::proto::Envelope robot;
  auto* tick = robot.mutable_robot_telemetry()->add_ticks();
  tick->set_t_ns(601 * s + s / 2);
  tick->set_outcome(link::proto::HEAD_TICK_SENT);
  tick->mutable_t_robot_head_command()->set_tx(0.25);
  tick->mutable_t_robot_head_measured()->set_qw(1);
  link::proto::Envelope xr;
  auto* t = xr.mutable_xr_telemetry();
  t->set_clock_synced(true);
  t->set_robot_to_xr_offset_ns(robot_to_xr);
  auto* f = t->add_frames();
  f->set_display_ns(609 * s);
  f->set_head_valid(true);
  f->mutable_t_vr_hmd()->set_ty(1.6);
  f->mutable_t_vr_hmd()->set_qw(1);
  f->set_new_image(true);
  f->mutable_stamps()->set_capture_ns(602 * s - 40'000'000);
  f->mutable_stamps()->set_displayed_ns(609 * s);
  f->set_eye_camera_distance_m(-1);
  link::proto::Envelope unsynced = xr;
  unsynced.mutable_xr_telemetry()->set_clock_synced(false);
  const std::vector<TelemetryBatch> batches = {{robot_to_utc, robot.SerializeAsString()},
                                               {robot_to_utc, xr.SerializeAsString()},
                                               {std::nullopt, xr.SerializeAsString()},  // no pong yet
                                               {robot_to_utc, unsynced.SerializeAsString()},
                                               {robot_to_utc, std::string("\xff\xff\xff", 3)}};
  const TrialTelemetry d = decodeTrialTelemetry(batches, start_utc);
  EXPECT_EQ(d.batches, 5u);
  EXPECT_EQ(d.unsynced_batches, 2u);
  EXPECT_EQ(d.undecodable_batches, 1u);
  ASSERT_EQ(d.robot.size(), 1u);
  EXPECT_DOUBLE_EQ(d.robot[0].t_s, 1.5);
  EXPECT_EQ(d.robot[0].outcome, "sent");
  EXPECT_DOUBLE_EQ(d.robot[0].cmd_x, 0.25);
  ASSERT_EQ(d.head.size(), 1u);
  EXPECT_DOUBLE_EQ(d.head[0].t_s, 2.0);
  EXPECT_DOUBLE_EQ(d.head[0].y, 1.6);
  EXPECT_NEAR(d.head[0].image_latency_ms, 40.0, 1e-9);
  EXPECT_TRUE(std::isnan(d.head[0].delta_s_m));
  EXPECT_EQ(utcNs("2026-11-24T12:00:00.250Z").value() % s, 250'000'000);
  EXPECT_FALSE(utcNs("yesterday"));
  // Written as two CSV files with a header each.
  const fs::path dir = freshDir("telemetry");
  std::string error;
  const auto files = writeTrialTelemetryCsv(d, (dir / "t").string(), &error);
  ASSERT_TRUE(files) << error;
  std::ifstream head((dir / "t_head.csv").string());
  std::string header, row;
  std::getline(head, header);
  std::getline(head, row);
  EXPECT_EQ(header.rfind("t_s,x_m,y_m,z_m", 0), 0u);
  EXPECT_EQ(row.rfind("2,0,1.6,0,1,", 0), 0u) << row;
  fs::remove_all(dir);
}

TEST(TrialRunner, ModeAcknowledgedThenTimedAttemptsOutcomesAndTheTimeLimit) {
  const fs::path dir = freshDir("runner");
  std::string error;
  auto store = StudyStore::open((dir / "s.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  StudyDefinition d = paperStudy();
  d.time_limit_s = 300;
  ASSERT_TRUE(store->startSession("P01", 1, d, trialOrder(d, 1), &error)) << error;
  const SessionRecord session = *store->findSession("P01", d.name);
  // The robot's replies come later, as control replies do.
  std::vector<std::pair<std::string, std::function<void(bool, const std::string&)>>> requests;
  TrialRunner runner(*store, session, d, [&](const std::string& mode, std::function<void(bool, const std::string&)> done) {
    requests.emplace_back(mode, std::move(done));
  });
  constexpr std::int64_t kS = 1'000'000'000;
  ASSERT_EQ(runner.state(), TrialRunner::State::kIdle);
  ASSERT_TRUE(runner.prepareNext());
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_EQ(requests[0].first, session.order[0]);
  EXPECT_FALSE(runner.start(0));  // not acknowledged yet
  EXPECT_NE(runner.lastError().find("acknowledged"), std::string::npos);
  requests[0].second(true, "");
  ASSERT_EQ(runner.state(), TrialRunner::State::kReady);
  ASSERT_TRUE(runner.start(10 * kS));
  ASSERT_TRUE(runner.attempt());
  ASSERT_TRUE(runner.attempt());
  EXPECT_FALSE(runner.tick(309 * kS));
  EXPECT_NEAR(runner.elapsedS(81 * kS), 71.0, 1e-9);
  ASSERT_TRUE(runner.succeed(81 * kS));
  EXPECT_EQ(runner.orderIndex(), 1);
  // The robot refuses the next mode: back to idle with the reason; asked again, it agrees.
  ASSERT_TRUE(runner.prepareNext());
  requests.back().second(false, "arm stopped");
  EXPECT_EQ(runner.state(), TrialRunner::State::kIdle);
  EXPECT_NE(runner.lastError().find("arm stopped"), std::string::npos);
  ASSERT_TRUE(runner.prepareNext());
  requests.back().second(true, "");
  ASSERT_TRUE(runner.start(100 * kS));
  EXPECT_FALSE(runner.tick(399 * kS));
  EXPECT_TRUE(runner.tick(400 * kS));  // the 300 s limit: a timeout
  // The third: an abort needs a reason.
  ASSERT_TRUE(runner.prepareNext());
  requests.back().second(true, "");
  ASSERT_TRUE(runner.start(500 * kS));
  EXPECT_FALSE(runner.abort(510 * kS, ""));
  ASSERT_TRUE(runner.abort(510 * kS, "exoskeleton reset"));
  EXPECT_EQ(runner.state(), TrialRunner::State::kDone);
  EXPECT_FALSE(runner.prepareNext());
  const auto trials = store->trials();
  ASSERT_EQ(trials.size(), 3u);
  EXPECT_EQ(trials[0].outcome, TrialOutcome::kSuccess);
  EXPECT_EQ(trials[0].attempts, 2);
  EXPECT_NEAR(trials[0].duration_s, 71.0, 1e-9);
  EXPECT_EQ(trials[1].outcome, TrialOutcome::kTimeout);
  EXPECT_EQ(trials[1].duration_s, 300.0);
  EXPECT_EQ(trials[2].outcome, TrialOutcome::kAbort);
  EXPECT_EQ(trials[2].abort_reason, "exoskeleton reset");
  for (int i = 0; i < 3; ++i) EXPECT_EQ(trials[std::size_t(i)].mode, session.order[std::size_t(i)]);
  store.reset();
  fs::remove_all(dir);
}

TEST(TrialRunner, AResumedSessionRunsTheInterruptedTrialAgain) {
  const fs::path dir = freshDir("resume");
  const fs::path db = dir / "s.sqlite";
  ASSERT_TRUE(runCrashWriter(db, "P01", 3, 0));  // killed during its first trial
  std::string error;
  auto store = StudyStore::open(db.string(), &error);
  ASSERT_TRUE(store) << error;
  StudyDefinition d = paperStudy();
  d.questionnaires = {paperLikert()};
  const auto session = store->findSession("P01", d.name);
  ASSERT_TRUE(session);
  TrialRunner runner(*store, *session, d, [](const std::string&, std::function<void(bool, const std::string&)> done) {
    done(true, "");
  });
  EXPECT_EQ(runner.orderIndex(), 0);  // the interrupted trial is run again
  ASSERT_TRUE(runner.prepareNext());
  ASSERT_TRUE(runner.start(0));
  ASSERT_TRUE(runner.succeed(5'000'000'000));
  EXPECT_EQ(runner.orderIndex(), 1);
  EXPECT_EQ(store->trials().size(), 2u);
  store.reset();
  fs::remove_all(dir);
}

/// A robot for the workflow that answers only when the test says so (as the link's replies come
/// later, on the GUI thread, or never), and an XR app that renders in whatever mode it is given.
class ScriptedStudyRobot final : public StudyRobot {
 public:
  void requestMode(link::proto::VisualMode mode, std::function<void(const Reply&)> done) override {
    modes.push_back(mode);
    pending.push_back(std::move(done));
  }
  void sendTrialIndicator(const link::proto::TrialIndicator& indicator, std::function<void(const Reply&)> done) override {
    indicators.push_back(indicator);
    pending.push_back(std::move(done));
  }
  std::optional<link::proto::VisualMode> xrVisualMode() const override { return xr_mode; }
  std::uint64_t robotInstance() const override { return instance; }
  /// Answers the oldest request; false when none waits.
  bool answer(const Reply& reply) {
    if (pending.empty()) return false;
    auto done = std::move(pending.front());
    pending.erase(pending.begin());
    done(reply);
    return true;
  }
  static Reply ok(const std::string& file = "", bool available = true, const std::string& remark = "") {
    Reply r;
    r.answered = r.ok = true;
    r.error = remark;
    r.recording.set_available(available);
    r.recording.set_active(!file.empty());
    r.recording.set_file(file);
    return r;
  }

  std::vector<link::proto::VisualMode> modes;
  std::vector<link::proto::TrialIndicator> indicators;
  std::vector<std::function<void(const Reply&)>> pending;
  std::optional<link::proto::VisualMode> xr_mode;
  std::uint64_t instance = 0;
};

constexpr std::int64_t kSecond = 1'000'000'000;

// Issue #30: a reply that comes after the workflow is gone (the administrator changed the
// participant or opened another study while the mode switch was pending) touches nothing. Under
// ASan a write into the freed runner would stop the test.
TEST(TrialWorkflow, RepliesAfterTheWorkflowIsGoneTouchNothing) {
  const fs::path dir = freshDir("workflow_gone");
  std::string error;
  auto store = StudyStore::open((dir / "s.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  const StudyDefinition d = paperStudy();
  ASSERT_TRUE(store->startSession("P01", 0, d, trialOrder(d, 0), &error)) << error;
  const auto session = store->findSession("P01", d.name);
  ScriptedStudyRobot robot;
  {
    TrialWorkflow workflow(*store, *session, d, robot);
    ASSERT_TRUE(workflow.prepareNext());
    EXPECT_EQ(workflow.runner().state(), TrialRunner::State::kSwitchingMode);
  }  // gone while the robot has not answered
  ASSERT_EQ(robot.pending.size(), 1u);
  EXPECT_TRUE(robot.answer(ScriptedStudyRobot::ok()));
  // A running trial's indicator reply after the workflow went, too.
  {
    TrialWorkflow workflow(*store, *session, d, robot);
    robot.xr_mode = link::toProto(*link::parseVisualMode(workflow.runner().mode()));
    ASSERT_TRUE(workflow.prepareNext());
    ASSERT_TRUE(robot.answer(ScriptedStudyRobot::ok()));
    workflow.tick(0);
    ASSERT_EQ(workflow.runner().state(), TrialRunner::State::kReady);
    ASSERT_TRUE(workflow.start(0));
    workflow.interrupt(kSecond, "another participant");
  }
  ASSERT_EQ(robot.pending.size(), 2u);  // indicator on and off, unanswered
  EXPECT_TRUE(robot.answer(ScriptedStudyRobot::ok("P01-full6d-db-t1.mcap")));
  EXPECT_TRUE(robot.answer(ScriptedStudyRobot::ok()));
  const auto trials = store->trials();
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].outcome, TrialOutcome::kInterrupted);
  EXPECT_EQ(trials[0].recording, "");  // the late reply wrote nothing
  store.reset();
  fs::remove_all(dir);
}

// The mode gate, the indicator and every refusal of the robot about the recording, shown and
// stored with the trial; a robot restarted mid-trial gets the indicator again and records part 2;
// names are unique across databases.
TEST(TrialWorkflow, ModeGateIndicatorAndRecordingRefusalsStoredWithTheTrial) {
  const fs::path dir = freshDir("workflow");
  std::string error;
  auto store = StudyStore::open((dir / "s.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  StudyDefinition d = paperStudy();
  d.time_limit_s = 60;
  ASSERT_TRUE(store->startSession("P07", 6, d, trialOrder(d, 6), &error)) << error;
  const auto session = store->findSession("P07", d.name);
  ScriptedStudyRobot robot;
  robot.instance = 11;
  TrialWorkflow workflow(*store, *session, d, robot);
  const auto messages = [&] {
    std::string all;
    for (const auto& m : workflow.takeMessages()) all += (m.error ? "! " : "") + m.text + "\n";
    return all;
  };

  // The XR app never confirms: refused after the timeout, with the reason.
  ASSERT_TRUE(workflow.prepareNext());
  ASSERT_TRUE(robot.answer(ScriptedStudyRobot::ok()));
  robot.xr_mode = link::proto::VISUAL_MODE_UNSPECIFIED;
  workflow.tick(0);
  workflow.tick(4 * kSecond);
  EXPECT_EQ(workflow.runner().state(), TrialRunner::State::kSwitchingMode);
  workflow.tick(6 * kSecond);
  EXPECT_EQ(workflow.runner().state(), TrialRunner::State::kIdle);
  EXPECT_NE(workflow.runner().lastError().find("did not confirm the mode"), std::string::npos) << workflow.runner().lastError();
  // Confirmed: ready.
  ASSERT_TRUE(workflow.prepareNext());
  ASSERT_TRUE(robot.answer(ScriptedStudyRobot::ok()));
  const std::string mode = workflow.runner().mode();
  robot.xr_mode = link::toProto(*link::parseVisualMode(mode));
  workflow.tick(7 * kSecond);
  ASSERT_EQ(workflow.runner().state(), TrialRunner::State::kReady);
  messages();

  // Started: the indicator carries the recording name; the robot has no record folder.
  ASSERT_TRUE(workflow.start(10 * kSecond));
  const std::int64_t trial = workflow.runner().trialId();
  ASSERT_FALSE(robot.indicators.empty());
  const std::string name = robot.indicators.back().recording_name();
  EXPECT_EQ(name, TrialWorkflow::recordingName("P07", mode, store->uid(), trial, 1));
  EXPECT_NE(name.find("-db" + store->uid() + "-t" + std::to_string(trial)), std::string::npos) << name;
  ASSERT_TRUE(robot.answer(ScriptedStudyRobot::ok("", false)));
  EXPECT_NE(messages().find("! trial recording: not recorded: the robot has no record folder"), std::string::npos);
  // The robot restarts 12.5 s in: the indicator again (elapsed advanced), part 2; it refuses to record.
  robot.instance = 12;
  workflow.tick(22'500'000'000);
  ASSERT_EQ(robot.indicators.size(), 2u);
  EXPECT_TRUE(robot.indicators.back().running());
  EXPECT_NEAR(robot.indicators.back().elapsed_s(), 12.5, 1e-9);
  EXPECT_EQ(robot.indicators.back().recording_name(), TrialWorkflow::recordingName("P07", mode, store->uid(), trial, 2));
  ASSERT_TRUE(robot.answer(ScriptedStudyRobot::ok("", true, "the trial runs, but is not recorded: the disk is full")));
  // Once more (it restarted again), and this time it records.
  robot.instance = 13;
  workflow.tick(30 * kSecond);
  ASSERT_TRUE(robot.answer(ScriptedStudyRobot::ok("/rec/" + robot.indicators.back().recording_name() + ".mcap")));
  ASSERT_TRUE(workflow.succeed(40 * kSecond));
  ASSERT_TRUE(robot.answer(ScriptedStudyRobot::ok()));  // the indicator off
  EXPECT_FALSE(robot.indicators.back().running());
  const auto trials = store->trials();
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].recording, "/rec/" + TrialWorkflow::recordingName("P07", mode, store->uid(), trial, 3) + ".mcap");
  EXPECT_EQ(trials[0].recording_note,
            "not recorded: the robot has no record folder (start it with --record-dir DIR); the robot restarted 12.5 s "
            "into the trial: recording part 2 from then on; the trial runs, but is not recorded: the disk is full; the "
            "robot restarted 20.0 s into the trial: recording part 3 from then on");

  // Another database, the same participant and trial id: another name.
  auto other = StudyStore::open((dir / "other.sqlite").string(), &error);
  ASSERT_TRUE(other) << error;
  EXPECT_NE(TrialWorkflow::recordingName("P07", mode, other->uid(), trial, 1),
            TrialWorkflow::recordingName("P07", mode, store->uid(), trial, 1));
  // The time limit ends a trial by itself (and the indicator goes off).
  ASSERT_TRUE(workflow.prepareNext());
  ASSERT_TRUE(robot.answer(ScriptedStudyRobot::ok()));
  robot.xr_mode = link::toProto(*link::parseVisualMode(workflow.runner().mode()));
  workflow.tick(41 * kSecond);
  ASSERT_TRUE(workflow.start(42 * kSecond));
  EXPECT_FALSE(workflow.tick(101 * kSecond));
  EXPECT_TRUE(workflow.tick(102 * kSecond));
  EXPECT_NE(messages().find("time limit (60 s) reached"), std::string::npos);
  EXPECT_FALSE(robot.indicators.back().running());
  EXPECT_EQ(store->trials().back().outcome, TrialOutcome::kTimeout);
  other.reset();
  store.reset();
  fs::remove_all(dir);
}

/// What seededStudy planned per mode: each position's final outcome, the successes' times, and how
/// many runs were interrupted before it (the console went away and the trial was run again).
struct PlannedMode {
  int positions = 0, successes = 0, interrupted_runs = 0, never_rerun = 0;
  std::vector<double> success_times;
};

/// Seeded trials and answers for 12 participants; a few positions are interrupted once or twice
/// before their run ends, and one is interrupted and never run again (the participant left).
std::map<std::string, PlannedMode> seededStudy(StudyStore& store, const StudyDefinition& d) {
  std::map<std::string, PlannedMode> plan;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> time(20, 300);
  std::uniform_int_distribution<int> likert(1, 7), coin(0, 9);
  std::string error;
  for (int p = 0; p < 12; ++p) {
    const std::string id = "P" + std::to_string(10 + p);
    const auto order = trialOrder(d, static_cast<std::uint64_t>(p));
    const auto session = store.startSession(id, p, d, order, &error);
    EXPECT_TRUE(session) << error;
    if (!session) return plan;
    for (int i = 0; i < 3; ++i) {
      const std::string& mode = order[static_cast<std::size_t>(i)];
      PlannedMode& planned = plan[mode];
      ++planned.positions;
      // Participants 3 and 8 see their second trial interrupted once, participant 5 its first twice.
      const int interruptions = (p == 3 || p == 8) && i == 1 ? 1 : p == 5 && i == 0 ? 2 : 0;
      for (int k = 0; k < interruptions; ++k) {
        const auto run = store.startTrial(*session, i, mode, 300, &error);
        EXPECT_TRUE(run && store.endTrial(*run, TrialOutcome::kInterrupted, 12.5, "", &error)) << error;
        ++planned.interrupted_runs;
      }
      // Participant 11 left during its last trial: interrupted, never run again.
      if (p == 11 && i == 2) {
        const auto run = store.startTrial(*session, i, mode, 300, &error);
        EXPECT_TRUE(run && store.endTrial(*run, TrialOutcome::kInterrupted, 40.0, "", &error)) << error;
        ++planned.interrupted_runs;
        ++planned.never_rerun;
        continue;
      }
      const auto trial = store.startTrial(*session, i, mode, 300, &error);
      EXPECT_TRUE(trial) << error;
      const int c = coin(rng);
      const TrialOutcome outcome = c < 7 ? TrialOutcome::kSuccess : c < 9 ? TrialOutcome::kTimeout : TrialOutcome::kAbort;
      const double duration = outcome == TrialOutcome::kTimeout ? 300 : time(rng);
      EXPECT_TRUE(store.endTrial(*trial, outcome, duration, outcome == TrialOutcome::kAbort ? "robot reset" : "", &error))
          << error;
      if (outcome == TrialOutcome::kSuccess) {
        ++planned.successes;
        planned.success_times.push_back(duration);
      }
    }
    for (const auto& mode : d.modes)
      for (const auto& item : paperLikert().items)
        EXPECT_TRUE(store.saveAnswer(*session, mode, "paper_likert", item.key, likert(rng), &error)) << error;
  }
  return plan;
}

TEST(StudySummary, TableIAndBoxStatsEqualAnIndependentComputation) {
  const fs::path dir = freshDir("summary");
  std::string error;
  auto store = StudyStore::open((dir / "s.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  const StudyDefinition d = paperStudy();
  const auto plan = seededStudy(*store, d);
  const auto trials = store->trials();
  const auto answers = store->answers();
  const StudySummary s = summarise(d.modes, trials, answers);
  ASSERT_EQ(s.table.size(), 3u);
  int interrupted_runs = 0;
  for (const ModeSummary& m : s.table) {
    // Against what the data was made to be: n is the positions the participants had (12 per
    // mode), each once, however often it was interrupted; k, the mean and the sample SD (two-pass
    // textbook formulas) come from the planned successes.
    const PlannedMode& planned = plan.at(m.mode);
    interrupted_runs += planned.interrupted_runs;
    const std::vector<double>& t = planned.success_times;
    double mean = 0;
    for (double v : t) mean += v / double(t.size());
    double var = 0;
    for (double v : t) var += (v - mean) * (v - mean) / double(t.size() - 1);
    EXPECT_EQ(m.trials, 12) << m.mode;
    EXPECT_EQ(m.trials, planned.positions) << m.mode;
    EXPECT_EQ(m.successes, planned.successes) << m.mode;
    EXPECT_EQ(m.interrupted, planned.interrupted_runs) << m.mode;
    EXPECT_EQ(m.successes + m.timeouts + m.fails + m.aborts + planned.never_rerun, m.trials) << m.mode;
    EXPECT_NEAR(m.mean_completion_s, mean, 1e-9);
    EXPECT_NEAR(m.sd_completion_s, std::sqrt(var), 1e-9);
  }
  EXPECT_EQ(interrupted_runs, 5);  // the data has interruptions: the rule above is exercised
  // Box statistics: R type 7 quartiles, 1-based h = (n − 1)·p + 1, against the definition.
  for (const auto& [key, by_mode] : s.items)
    for (const auto& [mode, b] : by_mode) {
      std::vector<double> v;
      for (const auto& a : answers)
        if (a.instrument == key.first && a.item == key.second && a.mode == mode) v.push_back(a.value);
      std::sort(v.begin(), v.end());
      const auto q = [&](double p) {
        const double h = (double(v.size()) - 1) * p + 1;
        const int lo = int(std::floor(h));
        return v[std::size_t(lo - 1)] + (h - lo) * (v[std::size_t(std::min<int>(lo, int(v.size()) - 1))] - v[std::size_t(lo - 1)]);
      };
      EXPECT_EQ(b.n, 12);
      EXPECT_NEAR(b.q1, q(0.25), 1e-12);
      EXPECT_NEAR(b.median, q(0.5), 1e-12);
      EXPECT_NEAR(b.q3, q(0.75), 1e-12);
      const double iqr = b.q3 - b.q1;
      std::size_t inside = 0;
      for (double x : v) {
        const bool out = x < b.q1 - 1.5 * iqr || x > b.q3 + 1.5 * iqr;
        inside += !out;
        if (!out) {
          EXPECT_GE(x, b.lower_whisker);
          EXPECT_LE(x, b.upper_whisker);
        }
      }
      EXPECT_EQ(inside + b.outliers.size(), v.size());
    }
  store.reset();
  fs::remove_all(dir);
}

TEST(TidyCsv, RoundTripsAndBadRowsNameTheirLine) {
  const fs::path dir = freshDir("csv");
  std::string error;
  auto store = StudyStore::open((dir / "s.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  const StudyDefinition d = paperStudy();
  seededStudy(*store, d);
  const auto session = store->findSession("P10", d.name);
  ASSERT_TRUE(session);
  const auto trials_before = store->trials();
  ASSERT_TRUE(store->setNotes(trials_before[0].id, "line one,\nline \"two\"", &error)) << error;
  ASSERT_TRUE(store->addRecording(trials_before[0].id, "recordings/P10-full6d-trial1.mcap", &error)) << error;
  ASSERT_TRUE(store->addRecording(trials_before[0].id, "recordings/P10-full6d-trial1-part2.mcap", &error)) << error;
  ASSERT_TRUE(store->addRecordingNote(trials_before[0].id, "the robot restarted at 3.2 s, \"part 2\"", &error)) << error;
  const auto trials = store->trials();
  const auto answers = store->answers();
  ASSERT_TRUE(writeTrialsCsv((dir / "t.csv").string(), trials, &error)) << error;
  ASSERT_TRUE(writeAnswersCsv((dir / "a.csv").string(), answers, &error)) << error;
  const auto t = readTrialsCsv((dir / "t.csv").string(), &error);
  const auto a = readAnswersCsv((dir / "a.csv").string(), &error);
  ASSERT_TRUE(t && a) << error;
  ASSERT_EQ(t->size(), trials.size());
  ASSERT_EQ(a->size(), answers.size());
  EXPECT_EQ((*t)[0].notes, "line one,\nline \"two\"");
  EXPECT_EQ((*t)[0].recording, "recordings/P10-full6d-trial1.mcap; recordings/P10-full6d-trial1-part2.mcap");
  EXPECT_EQ((*t)[0].recording_note, "the robot restarted at 3.2 s, \"part 2\"");
  EXPECT_EQ((*t)[1].recording, "");
  for (std::size_t i = 0; i < trials.size(); ++i) {
    EXPECT_EQ((*t)[i].participant, trials[i].participant);
    EXPECT_EQ((*t)[i].outcome, trials[i].outcome);
    EXPECT_NEAR((*t)[i].duration_s, trials[i].duration_s, 1e-6);
  }
  // Imported into a new database: the same summary.
  auto other = StudyStore::open((dir / "other.sqlite").string(), &error);
  ASSERT_TRUE(other) << error;
  ASSERT_TRUE(other->importRows(d, *t, *a, &error)) << error;
  const auto s1 = toJson(summarise(d.modes, trials, answers)), s2 = toJson(summarise(d.modes, other->trials(), other->answers()));
  EXPECT_EQ(s1["items"], s2["items"]);
  EXPECT_EQ(s1["table_i"].size(), s2["table_i"].size());
  for (std::size_t i = 0; i < s1["table_i"].size(); ++i)
    EXPECT_NEAR(s1["table_i"][i]["completion_time_mean_s"].get<double>(),
                s2["table_i"][i]["completion_time_mean_s"].get<double>(), 1e-6);
  // A bad row: refused with its line, nothing imported.
  {
    std::ofstream bad(dir / "bad.csv");
    bad << "participant,mode,instrument,item,value\nP1,full6d,paper_likert,fit,5\nP2,full7d,paper_likert,fit,5\n";
  }
  EXPECT_FALSE(readAnswersCsv((dir / "bad.csv").string(), &error));
  EXPECT_NE(error.find("bad.csv:3:"), std::string::npos) << error;
  EXPECT_NE(error.find("full7d"), std::string::npos) << error;
  {
    std::ofstream bad(dir / "bad_trials.csv");
    bad << "participant,order_index,mode,duration_s,outcome,attempts,time_limit_s\n"
           "P1,0,full6d,71,success,2,300\nP1,1,fixed,80,success,2.5,300\n";
  }
  EXPECT_FALSE(readTrialsCsv((dir / "bad_trials.csv").string(), &error));
  EXPECT_NE(error.find("bad_trials.csv:3:"), std::string::npos) << error;
  EXPECT_NE(error.find("whole numbers"), std::string::npos) << error;
  store.reset();
  other.reset();
  fs::remove_all(dir);
}

TEST(StudyReport, ThePapersAnswersReproduceItsFigure) {
  // The paper's questionnaire answers (7 participants × 7 items × 3 modes, from its user-study
  // figure's data; the pairing of values to participants is not in the paper, only per box).
  const fs::path dir = freshDir("report");
  std::string error;
  const auto answers = readAnswersCsv(std::string(TELESPHERE_SOURCE_DIR) + "/tests/console/data/paper_likert_answers.csv", &error);
  ASSERT_TRUE(answers) << error;
  ASSERT_EQ(answers->size(), 147u);
  auto store = StudyStore::open((dir / "paper.sqlite").string(), &error);
  ASSERT_TRUE(store) << error;
  StudyDefinition d = paperStudy();
  d.name = "paper";
  ASSERT_TRUE(store->importRows(d, {}, *answers, &error)) << error;
  const auto written = writeStudyReport(*store, (dir / "report").string(), &error);
  ASSERT_TRUE(written) << error;
  for (const char* name : {"study-paper_answers.csv", "study-paper_trials.csv", "study-paper_table-i.md",
                           "study-paper_summary.json", "study-paper_paper_likert.png", "study-paper_paper_likert.pdf",
                           "study.sqlite"})
    EXPECT_TRUE(fs::exists(dir / "report" / name)) << name;
  EXPECT_GT(fs::file_size(dir / "report" / "study-paper_paper_likert.png"), 20000u);
  // One of the figure's boxes: full 6D, "comfortable for your eyes": 6, 6, 5, 5, 7, 7, 7.
  const auto s = summarise(d.modes, {}, store->answers());
  const BoxStats& comfortable = s.items.at({"paper_likert", "comfortable"}).at("full6d");
  EXPECT_EQ(comfortable.median, 6.0);
  EXPECT_EQ(comfortable.q1, 5.5);
  EXPECT_EQ(comfortable.q3, 7.0);
  EXPECT_EQ(comfortable.lower_whisker, 5.0);
  EXPECT_NEAR(comfortable.mean, 43.0 / 7.0, 1e-12);
  const fs::path docs = fs::path(TELESPHERE_BINARY_DIR) / "console-screenshots";
  fs::create_directories(docs);
  fs::copy_file(dir / "report" / "study-paper_paper_likert.png", docs / "study_paper_likert.png",
                fs::copy_options::overwrite_existing);
  store.reset();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace telesphere::console::study

int main(int argc, char** argv) {
  if (!std::getenv("QT_QPA_PLATFORM")) setenv("QT_QPA_PLATFORM", "offscreen", 1);
  QApplication app(argc, argv);  // QtSql needs a core application; the report's plots a GUI one
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
