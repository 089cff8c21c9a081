// SPDX-License-Identifier: MIT
/// @brief The study report: CSV, Table I, box plots, summary.json, the database (study_report.h).
#include "console/study/study_report.h"

#include <QDir>
#include <algorithm>
#include <optional>
#include <cmath>
#include <fstream>
#include <map>
#include <qcustomplot.h>

#include "console/study/study_definition.h"
#include "console/study/tidy_csv.h"
#include "console/study/trial_telemetry.h"
#include "console/supervision/visual_mode_label.h"

namespace telesphere::console::study {
namespace {

std::string modeLabel(const std::string& mode) { return supervision::visualModeTitle(mode, "?"); }

QColor modeColour(std::size_t i) {
  const QColor colours[] = {QColor(0, 128, 0), QColor(230, 80, 40), QColor(40, 80, 220)};
  return colours[i % 3];
}

std::string fixed1(double v) {
  if (!std::isfinite(v)) return "–";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

/// Item texts of the instruments we know (else the key).
std::string itemText(const std::string& instrument, const std::string& item) {
  for (const Questionnaire& q : {paperLikert(), nasaTlxRaw(), systemUsabilityScale()})
    if (q.instrument == instrument)
      for (const QuestionnaireItem& i : q.items)
        if (i.key == item) return i.text;
  return item;
}

/// One trial's head motion against time: displacement from the first valid pose (x, y, z in cm,
/// VR frame), PNG.
bool writeHeadMotionPlot(const TrialTelemetry& telemetry, const std::string& title, const std::string& path,
                         std::string* error) {
  QCustomPlot plot;
  plot.plotLayout()->insertRow(0);
  plot.plotLayout()->addElement(0, 0, new QCPTextElement(&plot, QString::fromStdString(title)));
  const char* names[] = {"x (right)", "y (up)", "z (back)"};
  const QColor colours[] = {QColor(200, 40, 40), QColor(30, 140, 30), QColor(40, 80, 220)};
  for (int axis = 0; axis < 3; ++axis) {
    QCPGraph* g = plot.addGraph();
    g->setName(names[axis]);
    g->setPen(QPen(colours[axis], 1.5));
    QVector<double> t, v;
    std::optional<double> origin;
    for (const HeadSample& s : telemetry.head) {
      if (!s.head_valid) continue;
      const double p = axis == 0 ? s.x : axis == 1 ? s.y : s.z;
      if (!origin) origin = p;
      t.push_back(s.t_s);
      v.push_back(100.0 * (p - *origin));
    }
    g->setData(t, v, true);
  }
  plot.xAxis->setLabel("time since the trial started [s]");
  plot.yAxis->setLabel("head displacement since the trial started [cm]");
  plot.legend->setVisible(true);
  plot.rescaleAxes();
  const QCPRange y = plot.yAxis->range();
  const double margin = std::max(1.0, 0.08 * y.size());  // flat lines stay visible
  plot.yAxis->setRange(y.lower - margin, y.upper + margin);
  if (!plot.savePng(QString::fromStdString(path), 900, 420)) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

}  // namespace

bool writeLikertPlots(const StudySummary& summary, const std::vector<std::string>& modes,
                      const std::string& instrument, const std::string& path_stem, std::string* error) {
  std::vector<std::pair<std::string, const std::map<std::string, BoxStats>*>> items;
  for (const auto& [key, by_mode] : summary.items)
    if (key.first == instrument) items.emplace_back(key.second, &by_mode);
  if (items.empty()) {
    *error = "no answers for " + instrument;
    return false;
  }
  // The paper's order for its questionnaire; else as stored.
  if (instrument == "paper_likert") {
    std::vector<std::pair<std::string, const std::map<std::string, BoxStats>*>> ordered;
    for (const QuestionnaireItem& i : paperLikert().items)
      for (const auto& it : items)
        if (it.first == i.key) ordered.push_back(it);
    if (ordered.size() == items.size()) items = ordered;
  }
  QCustomPlot plot;
  const int width = 1100, height = 140 + 70 * static_cast<int>(items.size());
  plot.resize(width, height);
  plot.plotLayout()->insertRow(0);
  plot.plotLayout()->addElement(0, 0, new QCPTextElement(&plot, QString::fromStdString(
      instrument == "paper_likert" ? "Questionnaire answers per visual mode (paper user-study figure)" : instrument),
      QFont("sans", 11, QFont::Bold)));
  // Items down the key axis (y, first at the top), answers along x.
  QSharedPointer<QCPAxisTickerText> ticker(new QCPAxisTickerText);
  double lo = 1e9, hi = -1e9;
  std::vector<QCPAbstractPlottable*> in_legend(modes.size() + 1, nullptr);  // a box per mode, the mean
  for (std::size_t i = 0; i < items.size(); ++i) {
    const double y = static_cast<double>(i + 1);
    ticker->addTick(y, QString::fromStdString(itemText(instrument, items[i].first)));
    for (std::size_t m = 0; m < modes.size(); ++m) {
      const auto it = items[i].second->find(modes[m]);
      if (it == items[i].second->end()) continue;
      const BoxStats& b = it->second;
      const double key = y - 0.25 + 0.25 * static_cast<double>(m);
      auto* box = new QCPStatisticalBox(plot.yAxis, plot.xAxis);
      box->setName(QString::fromStdString(modeLabel(modes[m])));
      QVector<double> outliers(b.outliers.begin(), b.outliers.end());
      box->addData(key, b.lower_whisker, b.q1, b.median, b.q3, b.upper_whisker, outliers);
      box->setWidth(0.2);
      QColor fill = modeColour(m);
      fill.setAlpha(90);
      box->setBrush(fill);
      box->setPen(QPen(modeColour(m)));
      box->setMedianPen(QPen(modeColour(m).darker(), 3));
      box->setOutlierStyle(QCPScatterStyle(QCPScatterStyle::ssDisc, modeColour(m), 5));
      box->setWhiskerPen(QPen(modeColour(m), 1, Qt::DashLine));
      if (!in_legend[m]) in_legend[m] = box;
      auto* mean = plot.addGraph(plot.yAxis, plot.xAxis);
      mean->setLineStyle(QCPGraph::lsNone);
      mean->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCross, Qt::black, 8));
      mean->addData(key, b.mean);
      mean->setName("mean");
      if (!in_legend[modes.size()]) in_legend[modes.size()] = mean;
      for (double v : {b.lower_whisker, b.upper_whisker}) lo = std::min(lo, v), hi = std::max(hi, v);
      for (double v : b.outliers) lo = std::min(lo, v), hi = std::max(hi, v);
    }
  }
  plot.yAxis->setTicker(ticker);
  plot.yAxis->setRangeReversed(true);
  plot.yAxis->setRange(0.5, static_cast<double>(items.size()) + 0.5);
  plot.yAxis->grid()->setVisible(false);
  plot.xAxis->setLabel(instrument == "paper_likert" ? "answer (Likert 1–7, higher is better)" : "answer");
  if (instrument == "paper_likert") lo = std::min(lo, 1.0), hi = std::max(hi, 7.0);
  plot.xAxis->setRange(lo - 0.25, hi + 0.25);
  plot.legend->clearItems();
  for (QCPAbstractPlottable* p : in_legend)
    if (p) p->addToLegend();
  plot.legend->setVisible(true);
  plot.legend->setFont(QFont("sans", 9));
  // Below the plot, in one row, so that it hides no answer.
  plot.axisRect()->insetLayout()->take(plot.legend);
  plot.plotLayout()->addElement(2, 0, plot.legend);
  plot.legend->setFillOrder(QCPLegend::foColumnsFirst);
  plot.plotLayout()->setRowStretchFactor(2, 0.001);
  const bool png = plot.savePng(QString::fromStdString(path_stem + ".png"), width, height);
  const bool pdf = plot.savePdf(QString::fromStdString(path_stem + ".pdf"), width, height);
  if (!png || !pdf) {
    *error = "cannot write " + path_stem + (png ? ".pdf" : ".png");
    return false;
  }
  return true;
}

std::optional<std::vector<std::string>> writeStudyReport(const StudyStore& store, const std::string& dir,
                                                         std::string* error) {
  if (!QDir().mkpath(QString::fromStdString(dir))) {
    *error = "cannot create " + dir;
    return std::nullopt;
  }
  std::vector<std::string> written;
  const auto sessions = store.sessions();
  const auto trials = store.trials();
  const auto answers = store.answers();
  std::map<std::string, std::vector<std::string>> modes_of;  // study → modes (from its definition)
  std::map<std::int64_t, std::string> study_of_session;
  for (const SessionRecord& s : sessions) {
    study_of_session[s.id] = s.study_name;
    if (!modes_of.count(s.study_name)) {
      std::string why;
      const auto definition = StudyDefinition::parse(s.study_json, &why);
      modes_of[s.study_name] = definition ? definition->modes : StudyDefinition{}.modes;
    }
  }
  for (const auto& [study, modes] : modes_of) {
    std::vector<TrialRecord> study_trials;
    std::vector<AnswerRecord> study_answers;
    for (const TrialRecord& t : trials)
      if (study_of_session[t.session_id] == study) study_trials.push_back(t);
    for (const AnswerRecord& a : answers)
      if (study_of_session[a.session_id] == study) study_answers.push_back(a);
    const std::string stem = dir + "/study-" + study;
    if (!writeTrialsCsv(stem + "_trials.csv", study_trials, error) ||
        !writeAnswersCsv(stem + "_answers.csv", study_answers, error))
      return std::nullopt;
    written.push_back(stem + "_trials.csv");
    written.push_back(stem + "_answers.csv");
    const StudySummary summary = summarise(modes, study_trials, study_answers);
    std::ofstream md(stem + "_table-i.md"), csv(stem + "_table-i.csv");
    md << "| Visual mode | Success | Completion time mean [s] | StdDev [s] |\n|---|---:|---:|---:|\n";
    csv << "mode,successes,trials,completion_time_mean_s,completion_time_sd_s\n";
    for (const ModeSummary& m : summary.table) {
      md << "| " << modeLabel(m.mode) << " | " << m.successes << "/" << m.trials << " | " << fixed1(m.mean_completion_s)
         << " | " << fixed1(m.sd_completion_s) << " |\n";
      csv << m.mode << ',' << m.successes << ',' << m.trials << ',' << m.mean_completion_s << ',' << m.sd_completion_s
          << '\n';
    }
    int interrupted = 0;
    for (const ModeSummary& m : summary.table) interrupted += m.interrupted;
    if (interrupted > 0) {
      md << "\nn counts each participant's trial once, by how it finally ended; interrupted runs (the console "
            "went away), run again or not:";
      for (const ModeSummary& m : summary.table) md << ' ' << modeLabel(m.mode) << ' ' << m.interrupted << ';';
      md << " every run is in the trials CSV.\n";
    }
    written.push_back(stem + "_table-i.md");
    written.push_back(stem + "_table-i.csv");
    std::ofstream json(stem + "_summary.json");
    nlohmann::json j = toJson(summary);
    j["study"] = study;
    j["modes"] = modes;
    json << j.dump(2) << '\n';
    written.push_back(stem + "_summary.json");
    std::map<std::string, bool> instruments;
    for (const auto& [key, by_mode] : summary.items) instruments[key.first] = true;
    for (const auto& [instrument, unused] : instruments) {
      if (!writeLikertPlots(summary, modes, instrument, stem + "_" + instrument, error)) return std::nullopt;
      written.push_back(stem + "_" + instrument + ".png");
      written.push_back(stem + "_" + instrument + ".pdf");
    }
    if (!md || !csv || !json) {
      *error = "cannot write the summary files under " + dir;
      return std::nullopt;
    }
    // Each trial's telemetry (head poses, head loop, latencies) and its head motion.
    for (const TrialRecord& t : study_trials) {
      const auto batches = store.telemetry(t.id);
      if (batches.empty()) continue;
      const auto start = utcNs(t.started_utc);
      if (!start) continue;
      const TrialTelemetry telemetry = decodeTrialTelemetry(batches, *start);
      const std::string trial_stem = dir + "/telemetry/study-" + study + "_sub-" + t.participant + "_trial-" +
                                     std::to_string(t.order_index + 1) + "_mode-" + t.mode + "_id-" +
                                     std::to_string(t.id);
      QDir().mkpath(QString::fromStdString(dir + "/telemetry"));
      const auto files = writeTrialTelemetryCsv(telemetry, trial_stem, error);
      if (!files) return std::nullopt;
      written.insert(written.end(), files->begin(), files->end());
      const std::string title = "participant " + t.participant + ", trial " + std::to_string(t.order_index + 1) +
                                " (" + modeLabel(t.mode) + "), " + trialOutcomeName(t.outcome);
      if (!writeHeadMotionPlot(telemetry, title, trial_stem + "_head.png", error)) return std::nullopt;
      written.push_back(trial_stem + "_head.png");
    }
  }
  if (!store.copyTo(dir + "/study.sqlite", error)) return std::nullopt;
  written.push_back(dir + "/study.sqlite");
  return written;
}

}  // namespace telesphere::console::study
