// SPDX-License-Identifier: MIT
/// @brief CalibrationInUsePanel: the robot's and the XR app's calibration, the candidate's
///        changes, apply and revert through the session.
#include "console/widgets/calibration_in_use_panel.h"

#include <QDateTime>
#include <QHeaderView>
#include <QLabel>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>
#include <cmath>

#include "calib/calibration_file.h"
#include "calib/system_calibration_yaml.h"
#include "console/widgets/console_session.h"

namespace telesphere::console {

namespace {

const char* partsName(calibration::MeasuredParts parts) {
  return parts == calibration::MeasuredParts::kCameras ? "cameras and T_cam_l_cam_r"
                                                       : "T_flange_cam_l (T_robot_mount, T_wrist_marker)";
}

}  // namespace

CalibrationInUsePanel::CalibrationInUsePanel(ConsoleSession& session, QWidget* parent)
    : QWidget(parent), session_(session) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(4, 4, 4, 4);
  robot_ = new QLabel("Robot: –");
  robot_->setObjectName("calibration_in_use_robot");
  robot_->setWordWrap(true);
  xr_ = new QLabel("XR app: –");
  xr_->setObjectName("calibration_in_use_xr");
  xr_->setWordWrap(true);
  candidate_label_ = new QLabel("Candidate: none yet (a wizard's result that meets its done rule appears here)");
  candidate_label_->setObjectName("calibration_in_use_candidate");
  candidate_label_->setWordWrap(true);
  changes_ = new QTableWidget(0, 3);
  changes_->setObjectName("calibration_in_use_changes");
  changes_->setHorizontalHeaderLabels({"what Apply changes", "by", "how measured"});
  changes_->horizontalHeader()->setStretchLastSection(true);
  changes_->verticalHeader()->setVisible(false);
  changes_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  apply_ = new QPushButton("Apply to robot and XR app");
  apply_->setObjectName("calibration_apply");
  revert_ = new QPushButton("Revert");
  revert_->setObjectName("calibration_revert");
  log_ = new QPlainTextEdit;
  log_->setObjectName("calibration_in_use_log");
  log_->setReadOnly(true);
  log_->setMaximumBlockCount(200);
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(apply_);
  buttons->addWidget(revert_);
  buttons->addStretch(1);
  layout->addWidget(robot_);
  layout->addWidget(xr_);
  layout->addWidget(candidate_label_);
  layout->addWidget(changes_, 1);
  layout->addLayout(buttons);
  layout->addWidget(log_, 1);
  connect(apply_, &QPushButton::clicked, this, &CalibrationInUsePanel::apply);
  connect(revert_, &QPushButton::clicked, this, &CalibrationInUsePanel::revert);
  refresh();
}

std::optional<std::uint64_t> CalibrationInUsePanel::xrGeneration() const {
  return session_.telemetry().xrCalibrationGeneration();
}

std::optional<calib::SystemCalibration> CalibrationInUsePanel::nextCalibration() const {
  if (!candidate_ || !in_use_parsed_) return std::nullopt;
  return calibration::withMeasured(*in_use_parsed_, candidate_->result, candidate_->parts);
}

void CalibrationInUsePanel::setCandidate(const calib::SystemCalibration& result, calibration::MeasuredParts parts,
                                         const QString& source) {
  candidate_ = Candidate{result, parts, source};
  candidate_label_->setText("<b>Candidate:</b> " + source.toHtmlEscaped() + " — Apply replaces " + partsName(parts));
  showChanges();
  refresh();
}

void CalibrationInUsePanel::refresh() {
  const auto& state = session_.robotState();
  const bool robot_here = session_.robot().state() == supervision::PeerState::kConnected && state.has_value();
  if (robot_here && state->calibration_generation() != 0 &&
      (!in_use_ || in_use_->generation() != state->calibration_generation()))
    fetch();
  if (!in_use_) {
    robot_->setText(robot_here ? "<b>Robot:</b> asking for its calibration…" : "<b>Robot:</b> not connected");
  } else {
    robot_->setText(QString("<b>Robot uses generation %1</b>: %2%3")
                        .arg(in_use_->generation())
                        .arg(QString::fromStdString(in_use_->source()).toHtmlEscaped())
                        .arg(in_use_->previous() > 0
                                 ? QString(" · revert goes back to: %1 (%2 kept)")
                                       .arg(QString::fromStdString(in_use_->previous_source()).toHtmlEscaped())
                                       .arg(in_use_->previous())
                                 : QString(" · nothing earlier to revert to")) +
                        (in_use_->generation() <= 1 ? QString()
                         : !in_use_->saved_to().empty()
                             ? "<br>saved on the robot to " + QString::fromStdString(in_use_->saved_to()).toHtmlEscaped() +
                                   " (a restart with --calib that file keeps it)"
                             : "<br><b style='color:#b3261e'>not saved on the robot" +
                                   (in_use_->save_error().empty()
                                        ? QString(" (start it with --calib-save FILE)")
                                        : ": " + QString::fromStdString(in_use_->save_error()).toHtmlEscaped()) +
                                   ": a restart goes back to its --calib file</b>"));
  }
  const auto xr = xrGeneration();
  const bool xr_here = session_.xr().state() == supervision::PeerState::kConnected;
  if (!xr || !xr_here) {
    xr_->setText("<b>XR app:</b> <span style='color:#777'>not heard</span>");
  } else if (*xr == 0) {
    xr_->setText("<b>XR app:</b> <span style='color:#b26a00'>renders with its own start-up calibration</span>");
  } else if (in_use_ && *xr == in_use_->generation()) {
    xr_->setText(QString("<b>XR app:</b> <span style='color:#1b5e20'>renders with generation %1 (the robot's)</span>").arg(*xr));
  } else {
    xr_->setText(QString("<b>XR app:</b> <span style='color:#b26a00'>renders with generation %1, switching to the "
                         "robot's</span>").arg(*xr));
  }
  apply_->setEnabled(robot_here && candidate_changes_);
  apply_->setToolTip(candidate_ && !candidate_changes_ && in_use_
                         ? "The robot already uses this result"
                         : "The robot stamps its frames and moves the head with the new calibration from the next "
                           "frame; the XR app renders with it from the first frame stamped with it. Nothing restarts.");
  revert_->setEnabled(robot_here && in_use_ && in_use_->previous() > 0);
  revert_->setToolTip(in_use_ && in_use_->previous() > 0
                          ? "Back to: " + QString::fromStdString(in_use_->previous_source())
                          : QString("The robot has no earlier calibration"));
}

void CalibrationInUsePanel::fetch() {
  if (fetching_) return;
  fetching_ = true;
  link::proto::ControlRequest r;
  r.set_get_calibration(true);
  session_.request(std::move(r), "get_calibration", [this](const ControlOutcome& outcome) {
    fetching_ = false;
    if (outcome.ok && outcome.reply.has_calibration()) {
      takeInUse(outcome.reply.calibration());
    } else {
      log("the robot's calibration: " + outcome.text(), false);
    }
  });
}

void CalibrationInUsePanel::takeInUse(const link::proto::CalibrationInUse& in_use) {
  in_use_ = in_use;
  const auto parsed = calib::parseCalibration(in_use.yaml(), "the robot's calibration");
  if (parsed) {
    in_use_parsed_ = *parsed;
  } else {
    in_use_parsed_.reset();
    log(QString::fromStdString(parsed.error().describe()), false);
  }
  showChanges();
  refresh();
}

void CalibrationInUsePanel::showChanges() {
  changes_->setRowCount(0);
  candidate_changes_ = false;
  const auto next = nextCalibration();
  if (!next) return;
  for (const auto& d : calibration::differences(*in_use_parsed_, *next)) {
    candidate_changes_ = candidate_changes_ || !(d.value < 1e-9);  // NaN (cannot compare) counts as a change
    const int row = changes_->rowCount();
    changes_->insertRow(row);
    changes_->setItem(row, 0, new QTableWidgetItem(QString::fromStdString(d.what)));
    const QString value = std::isfinite(d.value) ? QString::number(d.value, 'f', d.unit == "°" ? 3 : 2) + " " +
                                                       QString::fromStdString(d.unit)
                                                 : QString("–");
    changes_->setItem(row, 1, new QTableWidgetItem(value));
    changes_->setItem(row, 2, new QTableWidgetItem(QString::fromStdString(d.detail)));
  }
  changes_->resizeColumnsToContents();
}

void CalibrationInUsePanel::apply() {
  const auto next = nextCalibration();
  if (!next) {
    log("nothing to apply: " + QString(!candidate_ ? "no wizard result yet" : "the robot's calibration is not known yet"),
        false);
    return;
  }
  link::proto::ControlRequest r;
  r.mutable_apply_calibration()->set_text(calib::toSystemCalibrationYaml(*next));
  r.mutable_apply_calibration()->set_source(candidate_->source.toStdString());
  const QString what = "apply " + candidate_->source;
  apply_->setEnabled(false);
  session_.request(std::move(r), what, [this](const ControlOutcome& outcome) { takeReply(outcome); });
}

void CalibrationInUsePanel::revert() {
  link::proto::ControlRequest r;
  r.set_revert_calibration(true);
  revert_->setEnabled(false);
  session_.request(std::move(r), "revert calibration", [this](const ControlOutcome& outcome) { takeReply(outcome); });
}

void CalibrationInUsePanel::takeReply(const ControlOutcome& outcome) {
  if (outcome.ok && outcome.reply.has_calibration()) takeInUse(outcome.reply.calibration());
  log(outcome.text(), outcome.ok);
  emit answered(outcome.ok, outcome.text());
  refresh();
}

void CalibrationInUsePanel::log(const QString& text, bool ok) {
  log_->appendHtml(QString("<span style='color:%1'>%2 %3</span>")
                       .arg(ok ? "#1b5e20" : "#b3261e")
                       .arg(QDateTime::currentDateTime().toString("HH:mm:ss"))
                       .arg(text.toHtmlEscaped()));
}

}  // namespace telesphere::console
