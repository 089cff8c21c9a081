// SPDX-License-Identifier: MIT
/// @brief Tidy CSV of trials and answers (see tidy_csv.h).
#include "console/study/tidy_csv.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>

namespace telesphere::console::study {
namespace {

std::string quoted(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

/// One record of RFC 4180 CSV (quoted fields may hold newlines); false at the end.
bool readRecord(std::istream& in, std::vector<std::string>* fields, int* line) {
  fields->clear();
  std::string field;
  bool quoted_field = false, any = false;
  char c;
  while (in.get(c)) {
    any = true;
    if (quoted_field) {
      if (c == '"') {
        if (in.peek() == '"') {
          in.get(c);
          field += '"';
        } else {
          quoted_field = false;
        }
      } else {
        if (c == '\n') ++*line;
        field += c;
      }
    } else if (c == '"') {
      quoted_field = true;
    } else if (c == ',') {
      fields->push_back(field);
      field.clear();
    } else if (c == '\n') {
      ++*line;
      break;
    } else if (c != '\r') {
      field += c;
    }
  }
  if (!any) return false;
  fields->push_back(field);
  return true;
}

template <typename Row>
std::optional<std::vector<Row>> readCsv(const std::string& path, const std::vector<std::string>& required,
                                        const std::function<bool(const std::map<std::string, std::string>&, Row*,
                                                                 std::string*)>& parse,
                                        std::string* error) {
  std::ifstream in(path);
  std::vector<std::string> header, fields;
  int line = 0;
  if (!in || !readRecord(in, &header, &line)) {
    *error = path + ": cannot read it";
    return std::nullopt;
  }
  for (const std::string& name : required)
    if (std::find(header.begin(), header.end(), name) == header.end()) {
      *error = path + ":1: no column '" + name + "'";
      return std::nullopt;
    }
  std::vector<Row> rows;
  while (true) {
    const int at = line + 1;
    if (!readRecord(in, &fields, &line)) break;
    if (fields.size() == 1 && fields[0].empty()) continue;  // blank line
    if (fields.size() != header.size()) {
      *error = path + ":" + std::to_string(at) + ": " + std::to_string(fields.size()) + " fields, the header has " +
               std::to_string(header.size());
      return std::nullopt;
    }
    std::map<std::string, std::string> cells;
    for (std::size_t i = 0; i < header.size(); ++i) cells[header[i]] = fields[i];
    Row row;
    std::string why;
    if (!parse(cells, &row, &why)) {
      *error = path + ":" + std::to_string(at) + ": " + why;
      return std::nullopt;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

bool toDouble(const std::string& s, double* out) {
  try {
    std::size_t used = 0;
    *out = std::stod(s, &used);
    return used == s.size() && std::isfinite(*out);
  } catch (...) {
    return false;
  }
}

}  // namespace

bool writeTrialsCsv(const std::string& path, const std::vector<TrialRecord>& trials, std::string* error) {
  std::ofstream out(path, std::ios::trunc);
  out.precision(10);
  out << "participant,session,order_index,mode,start_utc,end_utc,duration_s,success,outcome,attempts,time_limit_s,"
         "abort_reason,notes,recording,recording_note\n";
  for (const TrialRecord& t : trials)
    out << quoted(t.participant) << ',' << t.session_id << ',' << t.order_index << ',' << t.mode << ','
        << t.started_utc << ',' << t.ended_utc << ',' << t.duration_s << ','
        << (t.outcome == TrialOutcome::kSuccess ? 1 : 0) << ',' << trialOutcomeName(t.outcome) << ',' << t.attempts
        << ',' << t.time_limit_s << ',' << quoted(t.abort_reason) << ',' << quoted(t.notes) << ',' << quoted(t.recording)
        << ',' << quoted(t.recording_note) << '\n';
  if (!out) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

bool writeAnswersCsv(const std::string& path, const std::vector<AnswerRecord>& answers, std::string* error) {
  std::ofstream out(path, std::ios::trunc);
  out.precision(10);
  out << "participant,mode,instrument,item,value\n";
  for (const AnswerRecord& a : answers)
    out << quoted(a.participant) << ',' << a.mode << ',' << a.instrument << ',' << a.item << ',' << a.value << '\n';
  if (!out) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

std::optional<std::vector<TrialRecord>> readTrialsCsv(const std::string& path, std::string* error) {
  return readCsv<TrialRecord>(
      path, {"participant", "order_index", "mode", "duration_s", "outcome", "attempts", "time_limit_s"},
      [](const std::map<std::string, std::string>& c, TrialRecord* t, std::string* why) {
        const auto get = [&](const char* k) { const auto it = c.find(k); return it == c.end() ? std::string() : it->second; };
        t->participant = get("participant");
        t->mode = get("mode");
        t->started_utc = get("start_utc");
        t->ended_utc = get("end_utc");
        t->abort_reason = get("abort_reason");
        t->notes = get("notes");
        t->recording = get("recording");  // absent in files from before recordings
        t->recording_note = get("recording_note");  // absent in files from before v4
        double order = 0, attempts = 0;
        const auto outcome = parseTrialOutcome(get("outcome"));
        if (t->participant.empty()) return *why = "empty participant", false;
        if (!isVisualModeName(t->mode)) return *why = "mode '" + t->mode + "' is not full6d, orientation3d or fixed", false;
        if (!outcome || *outcome == TrialOutcome::kRunning)
          return *why = "outcome '" + get("outcome") + "' is not success, fail, timeout, abort or interrupted", false;
        t->outcome = *outcome;
        if (!toDouble(get("order_index"), &order) || !toDouble(get("attempts"), &attempts) ||
            !toDouble(get("duration_s"), &t->duration_s) || !toDouble(get("time_limit_s"), &t->time_limit_s) ||
            t->duration_s < 0 || t->time_limit_s <= 0 || attempts < 0 || order < 0)
          return *why = "order_index, attempts, duration_s and time_limit_s must be numbers ≥ 0 (time limit > 0)", false;
        if (order != std::floor(order) || attempts != std::floor(attempts) || order > 1000 || attempts > 1e6)
          return *why = "order_index and attempts must be whole numbers", false;
        t->order_index = static_cast<int>(order);
        t->attempts = static_cast<int>(attempts);
        return true;
      },
      error);
}

std::optional<std::vector<AnswerRecord>> readAnswersCsv(const std::string& path, std::string* error) {
  return readCsv<AnswerRecord>(
      path, {"participant", "mode", "instrument", "item", "value"},
      [](const std::map<std::string, std::string>& c, AnswerRecord* a, std::string* why) {
        a->participant = c.at("participant");
        a->mode = c.at("mode");
        a->instrument = c.at("instrument");
        a->item = c.at("item");
        if (a->participant.empty() || a->instrument.empty() || a->item.empty())
          return *why = "participant, instrument and item must not be empty", false;
        if (!isVisualModeName(a->mode)) return *why = "mode '" + a->mode + "' is not full6d, orientation3d or fixed", false;
        if (!toDouble(c.at("value"), &a->value)) return *why = "value '" + c.at("value") + "' is not a number", false;
        return true;
      },
      error);
}

}  // namespace telesphere::console::study
