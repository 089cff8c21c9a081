// SPDX-License-Identifier: MIT
/// @brief StudyStore: schema, migrations and one transaction per event (see study_store.h).
#include "console/study/study_store.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QSqlError>
#include <QSqlQuery>
#include <QVariant>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>

namespace telesphere::console::study {
namespace {

/// Schema steps: entry v-1 takes a database at user_version v-1 to v.
const std::vector<std::vector<const char*>>& migrations() {
  static const std::vector<std::vector<const char*>> steps = {
      {  // v1
       "CREATE TABLE sessions(id INTEGER PRIMARY KEY, participant TEXT NOT NULL, participant_index INTEGER NOT NULL,"
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
       " kind TEXT NOT NULL, detail TEXT NOT NULL DEFAULT '')"},
      {  // v2: each trial's telemetry, the link's envelopes as they arrived
       "CREATE TABLE trial_telemetry(id INTEGER PRIMARY KEY, trial_id INTEGER NOT NULL REFERENCES trials(id),"
       " robot_to_utc_ns INTEGER, envelope BLOB NOT NULL)",
       "CREATE INDEX trial_telemetry_by_trial ON trial_telemetry(trial_id, id)"},
      {  // v3: the session recording the robot wrote for the trial (robot/record), '' for none
       "ALTER TABLE trials ADD COLUMN recording TEXT NOT NULL DEFAULT ''"},
      {  // v4: the database's own id (recording names unique across databases), why a trial is not recorded
       "CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL)",
       "INSERT INTO meta(key, value) VALUES('uid', lower(hex(randomblob(4))))",
       "ALTER TABLE trials ADD COLUMN recording_note TEXT NOT NULL DEFAULT ''"},
  };
  return steps;
}

std::string lastError(const QSqlQuery& q) { return q.lastError().text().toStdString(); }

QVariant text(const std::string& s) { return QString::fromStdString(s); }

/// Runs `body` in one transaction; rolled back (and false, with the reason) if it fails.
bool inTransaction(QSqlDatabase db, std::string* error, const std::function<bool(std::string*)>& body) {
  if (!db.transaction()) {
    *error = "cannot start a transaction: " + db.lastError().text().toStdString();
    return false;
  }
  if (!body(error)) {
    db.rollback();
    return false;
  }
  if (!db.commit()) {
    *error = "cannot commit: " + db.lastError().text().toStdString();
    db.rollback();
    return false;
  }
  return true;
}

bool exec(QSqlQuery& q, std::string* error) {
  if (q.exec()) return true;
  *error = lastError(q);
  return false;
}

TrialRecord trialOf(const QSqlQuery& q) {
  TrialRecord t;
  t.id = q.value(0).toLongLong();
  t.session_id = q.value(1).toLongLong();
  t.participant = q.value(2).toString().toStdString();
  t.order_index = q.value(3).toInt();
  t.mode = q.value(4).toString().toStdString();
  t.started_utc = q.value(5).toString().toStdString();
  t.ended_utc = q.value(6).toString().toStdString();
  t.duration_s = q.value(7).toDouble();
  t.outcome = parseTrialOutcome(q.value(8).toString().toStdString()).value_or(TrialOutcome::kInterrupted);
  t.attempts = q.value(9).toInt();
  t.time_limit_s = q.value(10).toDouble();
  t.abort_reason = q.value(11).toString().toStdString();
  t.notes = q.value(12).toString().toStdString();
  t.recording = q.value(13).toString().toStdString();
  t.recording_note = q.value(14).toString().toStdString();
  return t;
}

constexpr const char* kTrialColumns =
    "t.id, t.session_id, s.participant, t.order_index, t.mode, t.started_utc, COALESCE(t.ended_utc, ''),"
    " COALESCE(t.duration_s, 0), t.outcome, t.attempts, t.time_limit_s, t.abort_reason, t.notes, t.recording,"
    " t.recording_note";

/// Who this process is, for the writer lock: "telesphere-console (pid 4242 on rig-pc) since …".
std::string writerIdentity() {
  std::string program = "a process";
  if (QFile comm("/proc/self/comm"); comm.open(QIODevice::ReadOnly)) program = comm.readAll().trimmed().toStdString();
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) host[0] = '?';
  return program + " (pid " + std::to_string(getpid()) + " on " + host + ") since " + utcNow();
}

/// Takes `<path>.writer` (flock, not blocking) and writes who holds it; the fd, or -1 with the reason.
int takeWriterLock(const std::string& path, std::string* error) {
  const std::string lock_path = path + ".writer";
  const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    *error = "cannot create the writer lock " + lock_path + ": " + std::strerror(errno);
    return -1;
  }
  if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
    char holder[512] = {};
    const ssize_t n = pread(fd, holder, sizeof holder - 1, 0);
    ::close(fd);
    std::string who = n > 0 ? std::string(holder, std::size_t(n)) : std::string("another process");
    while (!who.empty() && (who.back() == '\n' || who.back() == ' ')) who.pop_back();
    *error = path + " is open in " + who + ": close it there first (one console writes a study at a time)";
    return -1;
  }
  const std::string me = writerIdentity() + "\n";
  if (ftruncate(fd, 0) != 0 || pwrite(fd, me.data(), me.size(), 0) != ssize_t(me.size())) {
    // The lock holds without the text; a second opener then reads "another process".
  }
  return fd;
}

}  // namespace

const char* trialOutcomeName(TrialOutcome outcome) {
  switch (outcome) {
    case TrialOutcome::kRunning: return "running";
    case TrialOutcome::kSuccess: return "success";
    case TrialOutcome::kFail: return "fail";
    case TrialOutcome::kTimeout: return "timeout";
    case TrialOutcome::kAbort: return "abort";
    case TrialOutcome::kInterrupted: return "interrupted";
  }
  return "?";
}

std::optional<TrialOutcome> parseTrialOutcome(const std::string& name) {
  for (auto o : {TrialOutcome::kRunning, TrialOutcome::kSuccess, TrialOutcome::kFail, TrialOutcome::kTimeout,
                 TrialOutcome::kAbort, TrialOutcome::kInterrupted})
    if (name == trialOutcomeName(o)) return o;
  return std::nullopt;
}

std::string utcNow() {
  return QDateTime::currentDateTimeUtc().toString(Qt::ISODateWithMs).toStdString();
}

StudyStore::StudyStore(QString connection) : connection_(std::move(connection)) {}

StudyStore::~StudyStore() {
  {
    QSqlDatabase db = QSqlDatabase::database(connection_, false);
    if (db.isOpen()) db.close();
  }
  QSqlDatabase::removeDatabase(connection_);
  if (writer_lock_fd_ >= 0) ::close(writer_lock_fd_);  // the lock file stays: unlinking it would race a next opener
  if (!snapshot_path_.empty()) {
    for (const char* suffix : {"", "-wal", "-shm"}) QFile::remove(QString::fromStdString(snapshot_path_ + suffix));
  }
}

std::unique_ptr<StudyStore> StudyStore::openConnection(const std::string& path, bool read_only, std::string* error) {
  static std::atomic<int> counter{0};
  const QString connection = QString("telesphere_study_%1").arg(counter.fetch_add(1));
  if (!QSqlDatabase::isDriverAvailable("QSQLITE")) {
    *error = "Qt has no SQLite driver (install libqt6sql6-sqlite)";
    return nullptr;
  }
  std::unique_ptr<StudyStore> store(new StudyStore(connection));
  QSqlDatabase db = QSqlDatabase::addDatabase("QSQLITE", connection);
  db.setDatabaseName(QString::fromStdString(path));
  if (read_only) db.setConnectOptions("QSQLITE_OPEN_READONLY");
  if (!db.open()) {
    *error = "cannot open " + path + ": " + db.lastError().text().toStdString();
    return nullptr;
  }
  return store;
}

std::unique_ptr<StudyStore> StudyStore::openSnapshot(const std::string& path, std::string* error) {
  if (!QFile::exists(QString::fromStdString(path))) {
    *error = "no study database at " + path;
    return nullptr;
  }
  auto source = openConnection(path, true, error);
  if (!source) return nullptr;
  static std::atomic<int> counter{0};
  const std::string copy = QDir::temp().filePath(QString("telesphere-study-snapshot-%1-%2.sqlite")
                                                     .arg(getpid())
                                                     .arg(counter.fetch_add(1)))
                               .toStdString();
  if (!source->copyTo(copy, error)) return nullptr;
  source.reset();
  auto store = openConnection(copy, false, error);
  if (!store) {
    QFile::remove(QString::fromStdString(copy));
    return nullptr;
  }
  store->snapshot_path_ = copy;
  if (!store->migrate(error)) {
    *error = path + " (snapshot): " + *error;
    return nullptr;
  }
  return store;
}

std::unique_ptr<StudyStore> StudyStore::open(const std::string& path, std::string* error) {
  const int lock = takeWriterLock(path, error);
  if (lock < 0) return nullptr;
  auto store = openConnection(path, false, error);
  if (!store) {
    ::close(lock);
    return nullptr;
  }
  store->writer_lock_fd_ = lock;
  {
    QSqlDatabase db = QSqlDatabase::database(store->connection_);
    QSqlQuery q(db);
    for (const char* pragma : {"PRAGMA journal_mode=WAL", "PRAGMA synchronous=NORMAL", "PRAGMA foreign_keys=ON",
                               "PRAGMA busy_timeout=5000"})
      if (!q.exec(pragma)) {
        *error = path + ": " + lastError(q);
        return nullptr;
      }
    q.exec("PRAGMA journal_mode");
    if (!q.next() || q.value(0).toString() != "wal") {
      *error = path + ": the database would not switch to WAL";
      return nullptr;
    }
  }
  if (!store->migrate(error) || !store->markInterrupted(error)) {
    *error = path + ": " + *error;
    return nullptr;
  }
  return store;
}

bool StudyStore::migrate(std::string* error) {
  QSqlDatabase db = QSqlDatabase::database(connection_);
  QSqlQuery q(db);
  if (!q.exec("PRAGMA user_version") || !q.next()) {
    *error = "cannot read the schema version: " + lastError(q);
    return false;
  }
  const int version = q.value(0).toInt();
  if (version > kSchemaVersion) {
    *error = "written by a newer telesphere (schema " + std::to_string(version) + ", this build knows " +
             std::to_string(kSchemaVersion) + ")";
    return false;
  }
  for (int v = version; v < kSchemaVersion; ++v) {
    const bool ok = inTransaction(db, error, [&](std::string* why) {
      QSqlQuery step(db);
      for (const char* sql : migrations()[static_cast<std::size_t>(v)])
        if (!step.exec(sql)) {
          *why = "migration to schema " + std::to_string(v + 1) + ": " + lastError(step);
          return false;
        }
      if (!step.exec(QString("PRAGMA user_version=%1").arg(v + 1))) {
        *why = lastError(step);
        return false;
      }
      return true;
    });
    if (!ok) return false;
  }
  return true;
}

bool StudyStore::markInterrupted(std::string* error) {
  for (const TrialRecord& t : trials()) {
    if (t.outcome != TrialOutcome::kRunning) continue;
    QSqlDatabase db = QSqlDatabase::database(connection_);
    const bool ok = inTransaction(db, error, [&](std::string* why) {
      QSqlQuery q(db);
      q.prepare("UPDATE trials SET outcome='interrupted', ended_utc=?, abort_reason=? WHERE id=?");
      q.addBindValue(text(utcNow()));
      q.addBindValue(text("the console ended while the trial ran"));
      q.addBindValue(QVariant::fromValue<qlonglong>(t.id));
      return exec(q, why) && event(t.session_id, t.id, "trial_interrupted", "found running on open");
    });
    if (!ok) return false;
    TrialRecord marked = t;
    marked.outcome = TrialOutcome::kInterrupted;
    interrupted_.push_back(marked);
  }
  return true;
}

bool StudyStore::event(std::int64_t session_id, std::int64_t trial_id, const std::string& kind,
                       const std::string& detail) {
  QSqlQuery q(QSqlDatabase::database(connection_));
  q.prepare("INSERT INTO events(at_utc, session_id, trial_id, kind, detail) VALUES(?, ?, ?, ?, ?)");
  q.addBindValue(text(utcNow()));
  q.addBindValue(session_id ? QVariant::fromValue<qlonglong>(session_id) : QVariant());
  q.addBindValue(trial_id ? QVariant::fromValue<qlonglong>(trial_id) : QVariant());
  q.addBindValue(text(kind));
  q.addBindValue(text(detail));
  return q.exec();
}

std::optional<std::int64_t> StudyStore::startSession(const std::string& participant, std::int64_t participant_index,
                                                     const StudyDefinition& study,
                                                     const std::vector<std::string>& order, std::string* error) {
  if (participant.empty() || participant.find_first_of(",\"\n_/ ") != std::string::npos) {
    *error = "participant ID '" + participant + "': non-empty, without commas, quotes, '_', '/', spaces";
    return std::nullopt;
  }
  if (findSession(participant, study.name)) {
    *error = "participant " + participant + " already has a session in study " + study.name + " (resume it)";
    return std::nullopt;
  }
  QSqlDatabase db = QSqlDatabase::database(connection_);
  std::int64_t id = 0;
  const bool ok = inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare("INSERT INTO sessions(participant, participant_index, study_name, study_json, order_json, order_scheme,"
              " seed, started_utc) VALUES(?, ?, ?, ?, ?, ?, ?, ?)");
    q.addBindValue(text(participant));
    q.addBindValue(QVariant::fromValue<qlonglong>(participant_index));
    q.addBindValue(text(study.name));
    q.addBindValue(text(study.toJson()));
    q.addBindValue(text(nlohmann::json(order).dump()));
    q.addBindValue(text(study.order == OrderScheme::kCounterbalanced ? "counterbalanced" : "seeded_random"));
    q.addBindValue(QVariant::fromValue<qulonglong>(study.seed));
    q.addBindValue(text(utcNow()));
    if (!exec(q, why)) return false;
    id = q.lastInsertId().toLongLong();
    return event(id, 0, "session_start", participant);
  });
  if (!ok) return std::nullopt;
  return id;
}

std::optional<SessionRecord> StudyStore::findSession(const std::string& participant,
                                                     const std::string& study_name) const {
  for (const SessionRecord& s : sessions())
    if (s.participant == participant && s.study_name == study_name) return s;
  return std::nullopt;
}

bool StudyStore::endSession(std::int64_t session_id, std::string* error) {
  QSqlDatabase db = QSqlDatabase::database(connection_);
  return inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare("UPDATE sessions SET ended_utc=? WHERE id=?");
    q.addBindValue(text(utcNow()));
    q.addBindValue(QVariant::fromValue<qlonglong>(session_id));
    return exec(q, why) && event(session_id, 0, "session_end", "");
  });
}

std::optional<std::int64_t> StudyStore::startTrial(std::int64_t session_id, int order_index, const std::string& mode,
                                                   double time_limit_s, std::string* error) {
  QSqlDatabase db = QSqlDatabase::database(connection_);
  std::int64_t id = 0;
  const bool ok = inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare("INSERT INTO trials(session_id, order_index, mode, started_utc, outcome, time_limit_s)"
              " VALUES(?, ?, ?, ?, 'running', ?)");
    q.addBindValue(QVariant::fromValue<qlonglong>(session_id));
    q.addBindValue(order_index);
    q.addBindValue(text(mode));
    q.addBindValue(text(utcNow()));
    q.addBindValue(time_limit_s);
    if (!exec(q, why)) return false;
    id = q.lastInsertId().toLongLong();
    return event(session_id, id, "trial_start", mode);
  });
  if (!ok) return std::nullopt;
  return id;
}

bool StudyStore::addAttempt(std::int64_t trial_id, std::string* error) {
  QSqlDatabase db = QSqlDatabase::database(connection_);
  return inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare("UPDATE trials SET attempts = attempts + 1 WHERE id=? AND outcome='running'");
    q.addBindValue(QVariant::fromValue<qlonglong>(trial_id));
    if (!exec(q, why)) return false;
    if (q.numRowsAffected() != 1) {
      *why = "trial " + std::to_string(trial_id) + " is not running";
      return false;
    }
    return event(0, trial_id, "attempt", "");
  });
}

bool StudyStore::setNotes(std::int64_t trial_id, const std::string& notes, std::string* error) {
  QSqlDatabase db = QSqlDatabase::database(connection_);
  return inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare("UPDATE trials SET notes=? WHERE id=?");
    q.addBindValue(text(notes));
    q.addBindValue(QVariant::fromValue<qlonglong>(trial_id));
    // Saved on every keystroke: the event says how long, the trial row holds the text.
    return exec(q, why) && event(0, trial_id, "notes", std::to_string(notes.size()) + " bytes");
  });
}

bool StudyStore::appendToTrial(std::int64_t trial_id, const char* column, const std::string& value,
                               const std::string& event_kind, std::string* error) {
  QSqlDatabase db = QSqlDatabase::database(connection_);
  return inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare(QString("UPDATE trials SET %1 = CASE WHEN %1 = '' THEN ? ELSE %1 || '; ' || ? END WHERE id=?").arg(column));
    q.addBindValue(text(value));
    q.addBindValue(text(value));
    q.addBindValue(QVariant::fromValue<qlonglong>(trial_id));
    if (!exec(q, why)) return false;
    if (q.numRowsAffected() != 1) {
      *why = "no trial " + std::to_string(trial_id);
      return false;
    }
    return event(0, trial_id, event_kind, value);
  });
}

bool StudyStore::addRecording(std::int64_t trial_id, const std::string& file, std::string* error) {
  return appendToTrial(trial_id, "recording", file, "recording", error);
}

bool StudyStore::addRecordingNote(std::int64_t trial_id, const std::string& note, std::string* error) {
  return appendToTrial(trial_id, "recording_note", note, "recording_note", error);
}

std::string StudyStore::uid() const {
  QSqlQuery q(QSqlDatabase::database(connection_));
  if (q.exec("SELECT value FROM meta WHERE key='uid'") && q.next()) return q.value(0).toString().toStdString();
  return "";
}

bool StudyStore::endTrial(std::int64_t trial_id, TrialOutcome outcome, double duration_s,
                          const std::string& abort_reason, std::string* error) {
  if (outcome == TrialOutcome::kRunning) {
    *error = "a trial cannot end as running";
    return false;
  }
  if (outcome == TrialOutcome::kAbort && abort_reason.empty()) {
    *error = "an aborted trial needs a reason";
    return false;
  }
  QSqlDatabase db = QSqlDatabase::database(connection_);
  return inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare("UPDATE trials SET outcome=?, ended_utc=?, duration_s=?, abort_reason=? WHERE id=? AND outcome='running'");
    q.addBindValue(text(trialOutcomeName(outcome)));
    q.addBindValue(text(utcNow()));
    q.addBindValue(duration_s);
    q.addBindValue(text(abort_reason));
    q.addBindValue(QVariant::fromValue<qlonglong>(trial_id));
    if (!exec(q, why)) return false;
    if (q.numRowsAffected() != 1) {
      *why = "trial " + std::to_string(trial_id) + " is not running";
      return false;
    }
    return event(0, trial_id, "trial_end", trialOutcomeName(outcome));
  });
}

bool StudyStore::saveAnswer(std::int64_t session_id, const std::string& mode, const std::string& instrument,
                            const std::string& item, double value, std::string* error) {
  QSqlDatabase db = QSqlDatabase::database(connection_);
  return inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare("INSERT INTO answers(session_id, mode, instrument, item, value, answered_utc) VALUES(?, ?, ?, ?, ?, ?)"
              " ON CONFLICT(session_id, mode, instrument, item) DO UPDATE SET value=excluded.value,"
              " answered_utc=excluded.answered_utc");
    q.addBindValue(QVariant::fromValue<qlonglong>(session_id));
    q.addBindValue(text(mode));
    q.addBindValue(text(instrument));
    q.addBindValue(text(item));
    q.addBindValue(value);
    q.addBindValue(text(utcNow()));
    return exec(q, why) && event(session_id, 0, "answer", mode + " " + instrument + " " + item);
  });
}

bool StudyStore::addTelemetry(std::int64_t trial_id, const std::vector<TelemetryBatch>& batches, std::string* error) {
  if (batches.empty()) return true;
  QSqlDatabase db = QSqlDatabase::database(connection_);
  return inTransaction(db, error, [&](std::string* why) {
    QSqlQuery q(db);
    q.prepare("INSERT INTO trial_telemetry(trial_id, robot_to_utc_ns, envelope) VALUES(?, ?, ?)");
    for (const TelemetryBatch& b : batches) {
      q.addBindValue(QVariant::fromValue<qlonglong>(trial_id));
      q.addBindValue(b.robot_to_utc_ns ? QVariant::fromValue<qlonglong>(*b.robot_to_utc_ns) : QVariant());
      q.addBindValue(QByteArray(b.envelope.data(), static_cast<qsizetype>(b.envelope.size())));
      if (!exec(q, why)) return false;
    }
    return true;
  });
}

std::vector<TelemetryBatch> StudyStore::telemetry(std::int64_t trial_id) const {
  std::vector<TelemetryBatch> out;
  QSqlQuery q(QSqlDatabase::database(connection_));
  q.prepare("SELECT robot_to_utc_ns, envelope FROM trial_telemetry WHERE trial_id=? ORDER BY id");
  q.addBindValue(QVariant::fromValue<qlonglong>(trial_id));
  q.exec();
  while (q.next()) {
    TelemetryBatch b;
    if (!q.value(0).isNull()) b.robot_to_utc_ns = q.value(0).toLongLong();
    const QByteArray bytes = q.value(1).toByteArray();
    b.envelope.assign(bytes.constData(), static_cast<std::size_t>(bytes.size()));
    out.push_back(std::move(b));
  }
  return out;
}

std::vector<SessionRecord> StudyStore::sessions() const {
  std::vector<SessionRecord> out;
  QSqlQuery q(QSqlDatabase::database(connection_));
  q.exec("SELECT id, participant, participant_index, study_name, study_json, order_json, order_scheme, seed,"
         " started_utc, COALESCE(ended_utc, '') FROM sessions ORDER BY id");
  while (q.next()) {
    SessionRecord s;
    s.id = q.value(0).toLongLong();
    s.participant = q.value(1).toString().toStdString();
    s.participant_index = q.value(2).toLongLong();
    s.study_name = q.value(3).toString().toStdString();
    s.study_json = q.value(4).toString().toStdString();
    try {
      s.order = nlohmann::json::parse(q.value(5).toString().toStdString()).get<std::vector<std::string>>();
    } catch (...) {
    }
    s.order_scheme = q.value(6).toString().toStdString();
    s.seed = q.value(7).toULongLong();
    s.started_utc = q.value(8).toString().toStdString();
    s.ended_utc = q.value(9).toString().toStdString();
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<TrialRecord> StudyStore::trials() const {
  std::vector<TrialRecord> out;
  QSqlQuery q(QSqlDatabase::database(connection_));
  q.exec(QString("SELECT %1 FROM trials t JOIN sessions s ON s.id = t.session_id ORDER BY t.session_id, t.order_index, t.id")
             .arg(kTrialColumns));
  while (q.next()) out.push_back(trialOf(q));
  return out;
}

std::vector<AnswerRecord> StudyStore::answers() const {
  std::vector<AnswerRecord> out;
  QSqlQuery q(QSqlDatabase::database(connection_));
  q.exec("SELECT a.session_id, s.participant, a.mode, a.instrument, a.item, a.value, a.answered_utc FROM answers a"
         " JOIN sessions s ON s.id = a.session_id ORDER BY a.session_id, a.mode, a.instrument, a.item");
  while (q.next()) {
    AnswerRecord a;
    a.session_id = q.value(0).toLongLong();
    a.participant = q.value(1).toString().toStdString();
    a.mode = q.value(2).toString().toStdString();
    a.instrument = q.value(3).toString().toStdString();
    a.item = q.value(4).toString().toStdString();
    a.value = q.value(5).toDouble();
    a.answered_utc = q.value(6).toString().toStdString();
    out.push_back(std::move(a));
  }
  return out;
}

bool StudyStore::importRows(const StudyDefinition& study, const std::vector<TrialRecord>& trials,
                            const std::vector<AnswerRecord>& answers, std::string* error) {
  QSqlDatabase db = QSqlDatabase::database(connection_);
  std::map<std::string, std::int64_t> session_of;
  for (const SessionRecord& s : sessions())
    if (s.study_name == study.name) session_of[s.participant] = s.id;
  std::int64_t next_index = static_cast<std::int64_t>(session_of.size());
  return inTransaction(db, error, [&](std::string* why) {
    const auto session = [&](const std::string& participant) -> std::optional<std::int64_t> {
      if (const auto it = session_of.find(participant); it != session_of.end()) return it->second;
      QSqlQuery q(db);
      q.prepare("INSERT INTO sessions(participant, participant_index, study_name, study_json, order_json, order_scheme,"
                " seed, started_utc) VALUES(?, ?, ?, ?, '[]', 'imported', 0, ?)");
      q.addBindValue(text(participant));
      q.addBindValue(QVariant::fromValue<qlonglong>(next_index++));
      q.addBindValue(text(study.name));
      q.addBindValue(text(study.toJson()));
      q.addBindValue(text(utcNow()));
      if (!exec(q, why)) return std::nullopt;
      return session_of[participant] = q.lastInsertId().toLongLong();
    };
    for (const TrialRecord& t : trials) {
      const auto s = session(t.participant);
      if (!s) return false;
      QSqlQuery q(db);
      q.prepare("INSERT INTO trials(session_id, order_index, mode, started_utc, ended_utc, duration_s, outcome, attempts,"
                " time_limit_s, abort_reason, notes, recording, recording_note) VALUES(?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
      for (const QVariant& v :
           {QVariant::fromValue<qlonglong>(*s), QVariant(t.order_index), text(t.mode), text(t.started_utc),
            text(t.ended_utc), QVariant(t.duration_s), text(trialOutcomeName(t.outcome)), QVariant(t.attempts),
            QVariant(t.time_limit_s), text(t.abort_reason), text(t.notes), text(t.recording), text(t.recording_note)})
        q.addBindValue(v);
      if (!exec(q, why)) return false;
    }
    for (const AnswerRecord& a : answers) {
      const auto s = session(a.participant);
      if (!s) return false;
      QSqlQuery q(db);
      q.prepare("INSERT INTO answers(session_id, mode, instrument, item, value, answered_utc) VALUES(?, ?, ?, ?, ?, ?)");
      for (const QVariant& v : {QVariant::fromValue<qlonglong>(*s), text(a.mode), text(a.instrument), text(a.item),
                                QVariant(a.value), text(a.answered_utc.empty() ? utcNow() : a.answered_utc)})
        q.addBindValue(v);
      if (!exec(q, why)) {
        *why = "answer " + a.participant + " " + a.mode + " " + a.item + ": " + *why;
        return false;
      }
    }
    return event(0, 0, "import", std::to_string(trials.size()) + " trials, " + std::to_string(answers.size()) + " answers");
  });
}

bool StudyStore::copyTo(const std::string& path, std::string* error) const {
  QFile::remove(QString::fromStdString(path));
  QSqlQuery q(QSqlDatabase::database(connection_));
  q.prepare("VACUUM INTO ?");
  q.addBindValue(text(path));
  if (!q.exec()) {
    *error = "cannot copy the database to " + path + ": " + lastError(q);
    return false;
  }
  return true;
}

}  // namespace telesphere::console::study
