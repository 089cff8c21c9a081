// SPDX-License-Identifier: MIT
/// @brief HandEyePanel (see hand_eye_panel.h).
#include "console/widgets/hand_eye_panel.h"

#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMetaObject>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QSplitter>
#include <QTabWidget>
#include <QTableWidget>
#include <QVBoxLayout>
#include <chrono>
#include <cmath>
#include <qcustomplot.h>

#include "calib/calibration_file.h"
#include "console/widgets/calibration_save_dialog.h"
#include "robot/link/link_client.h"

namespace telesphere::console {
namespace {

constexpr double kSpreadScaleDeg = 45.0;  ///< the meter's full scale (two perpendicular axes used alike)

QString vectorText(const Eigen::Vector3d& v, int precision) {
  return QString("%1, %2, %3").arg(v.x(), 0, 'f', precision).arg(v.y(), 0, 'f', precision).arg(v.z(), 0, 'f', precision);
}

void setMeter(QProgressBar* bar, const QString& what, double spread_deg, double needed_deg) {
  bar->setValue(int(std::lround(std::min(spread_deg, kSpreadScaleDeg) * 10)));
  bar->setFormat(QString("%1 rotation axes spread %2° (need %3°)").arg(what).arg(spread_deg, 0, 'f', 1).arg(needed_deg, 0, 'f', 0));
  bar->setStyleSheet(spread_deg >= needed_deg ? "QProgressBar::chunk { background: #3a3; }"
                                              : "QProgressBar::chunk { background: #e90; }");
}

}  // namespace

HandEyePanel::HandEyePanel(const link::LinkEndpoints& endpoints, QWidget* parent)
    : QWidget(parent), endpoints_(endpoints) {
  auto* layout = new QVBoxLayout(this);
  rule_ = new QLabel;
  rule_->setObjectName("handeye_rule");
  rule_->setWordWrap(true);
  layout->addWidget(rule_);
  cameras_ = new QLabel("Cameras: none loaded (Load… a calibration with both cameras' intrinsics and T_cam_l_cam_r).");
  cameras_->setObjectName("handeye_cameras");
  cameras_->setWordWrap(true);
  layout->addWidget(cameras_);

  auto* row = new QHBoxLayout;
  load_ = new QPushButton("Load cameras…");
  amplitude_ = new QDoubleSpinBox;
  amplitude_->setObjectName("handeye_amplitude");
  amplitude_->setRange(0.0, 30.0);
  amplitude_->setValue(20.0);
  amplitude_->setSuffix("° head pattern");
  amplitude_->setToolTip("yaw amplitude of the head's sinusoidal pattern (pitch 0.6×, roll 0.4×); 0: the head holds still");
  start_ = new QPushButton("Start");
  start_->setObjectName("handeye_start");
  start_->setToolTip("the head runs the pattern; move the manipulator with the marker in view (teach mode)");
  cancel_button_ = new QPushButton("Cancel");
  delete_ = new QPushButton("Delete sample");
  outliers_ = new QPushButton("Remove outliers");
  save_ = new QPushButton("Save…");
  load_->setObjectName("handeye_load");
  cancel_button_->setObjectName("handeye_cancel");
  delete_->setObjectName("handeye_delete");
  outliers_->setObjectName("handeye_outliers");
  save_->setObjectName("handeye_save");
  for (QWidget* w : std::initializer_list<QWidget*>{load_, amplitude_, start_, cancel_button_}) row->addWidget(w);
  row->addStretch(1);
  for (QWidget* w : std::initializer_list<QWidget*>{delete_, outliers_, save_}) row->addWidget(w);
  layout->addLayout(row);

  auto* meters = new QGridLayout;
  head_spread_ = new QProgressBar;
  head_spread_->setObjectName("handeye_head_spread");
  wrist_spread_ = new QProgressBar;
  wrist_spread_->setObjectName("handeye_wrist_spread");
  for (QProgressBar* bar : {head_spread_, wrist_spread_}) {
    bar->setRange(0, int(kSpreadScaleDeg * 10));
    bar->setTextVisible(true);
  }
  meters->addWidget(new QLabel("<b>Rotation diversity</b>"), 0, 0, 1, 2);
  meters->addWidget(head_spread_, 1, 0);
  meters->addWidget(wrist_spread_, 1, 1);
  layout->addLayout(meters);
  status_ = new QLabel("No hand-eye run yet.");
  status_->setObjectName("handeye_status");
  status_->setWordWrap(true);
  layout->addWidget(status_);

  auto* tabs = new QTabWidget;
  tabs->setObjectName("handeye_tabs");
  auto* page = new QWidget;
  auto* page_layout = new QVBoxLayout(page);
  page_layout->setContentsMargins(0, 0, 0, 0);
  results_ = new QTableWidget(3, 4);
  results_->setObjectName("handeye_results");
  results_->setHorizontalHeaderLabels({"translation (mm)", "σ translation (mm)", "rotation vector (°)", "σ rotation (°)"});
  results_->setVerticalHeaderLabels({"T_flange_cam_l", "T_robot_mount", "T_wrist_marker"});
  results_->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
  results_->setMaximumHeight(118);
  page_layout->addWidget(results_);
  auto* split = new QSplitter(Qt::Horizontal);
  samples_ = new QTableWidget(0, 5);
  samples_->setObjectName("handeye_samples");
  samples_->setHorizontalHeaderLabels({"marker in", "head °", "wrist °", "RMS px", ""});
  samples_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  samples_->horizontalHeader()->setStretchLastSection(true);
  samples_->setSelectionBehavior(QAbstractItemView::SelectRows);
  samples_->setSelectionMode(QAbstractItemView::SingleSelection);
  samples_->setToolTip("head ° and wrist °: rotation from sample 1");
  split->addWidget(samples_);
  plot_ = new QCustomPlot;
  plot_->setObjectName("handeye_residual_plot");
  plot_->setMinimumHeight(200);
  plot_->xAxis->setLabel("sample");
  plot_->yAxis->setLabel("reprojection RMS (px)");
  plot_->legend->setVisible(true);
  plot_->legend->setFont(QFont(font().family(), 8));
  plot_->legend->setBrush(QColor(255, 255, 255, 210));
  split->addWidget(plot_);
  split->setSizes({260, 440});
  page_layout->addWidget(split, 1);
  tabs->addTab(page, "Result");
  log_ = newCalibrationLog("handeye_log");
  tabs->addTab(log_, "Log");
  layout->addWidget(tabs, 1);

  connect(load_, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, "Cameras for the hand-eye calibration", QString(),
                                                      "calibration (*.yaml *.json)");
    if (path.isEmpty()) return;
    QString error;
    if (!loadCameras(path, &error)) status_->setText("<span style='color:#b00'>" + error.toHtmlEscaped() + "</span>");
  });
  connect(start_, &QPushButton::clicked, this, &HandEyePanel::start);
  connect(cancel_button_, &QPushButton::clicked, this, &HandEyePanel::cancel);
  connect(delete_, &QPushButton::clicked, this, [this] {
    if (samples_->currentRow() >= 0) deleteSample(samples_->currentRow());
  });
  connect(outliers_, &QPushButton::clicked, this, &HandEyePanel::removeOutliers);
  connectCalibrationSave(save_, this, status_,
                         [this](const QString& path, const QString& format, QString* error) { return saveTo(path, format, error); });
  setProcedureOptions({});
  setMeter(head_spread_, "head", 0, options_.collector.rule.min_axis_spread_deg);
  setMeter(wrist_spread_, "wrist", 0, options_.collector.rule.min_axis_spread_deg);
  setBusy(false);
}

HandEyePanel::~HandEyePanel() { worker_.stop(); }

void HandEyePanel::setProcedureOptions(const calibration::HandEyeProcedureOptions& options) {
  options_ = options;
  rule_->setText("<b>Done when:</b> " + QString::fromStdString(options_.collector.rule.describe()) +
                 QString(" · a solve from %1 samples on, again on every new one").arg(options_.collector.auto_solve_from));
  amplitude_->setValue(options_.pattern_amplitude_deg);
  if (options_.cameras.cameras.size() == 2 && options_.cameras.T_cam_l_cam_r) {
    const auto& c = options_.cameras.cameras[0];
    cameras_->setText(QString("Cameras: %1 (%2, %3×%4), T_cam_l_cam_r held fixed · marker %5 id %6, %7 mm")
                          .arg(cameras_path_.isEmpty() ? "as given" : cameras_path_)
                          .arg(QString::fromStdString(std::string(c.camera.modelName())))
                          .arg(c.width)
                          .arg(c.height)
                          .arg(QString::fromStdString(options_.marker.dictionary))
                          .arg(options_.marker.id)
                          .arg(options_.marker.size_m * 1000.0, 0, 'f', 0));
  }
  if (!running()) setBusy(false);
}

bool HandEyePanel::loadCameras(const QString& path, QString* error) {
  auto loaded = calib::loadCalibrationFile(path.toStdString());
  if (!loaded) {
    *error = QString::fromStdString(loaded.error().describe());
    return false;
  }
  if (loaded->cameras.size() != 2 || !loaded->T_cam_l_cam_r) {
    *error = path + ": needs both cameras' intrinsics and T_cam_l_cam_r (calibrate the intrinsics first)";
    return false;
  }
  cameras_path_ = path;
  calibration::HandEyeProcedureOptions o = options_;
  o.cameras = *loaded;
  setProcedureOptions(o);
  return true;
}

QString HandEyePanel::statusText() const { return status_->text(); }

void HandEyePanel::setBusy(bool busy) {
  const bool has_cameras = options_.cameras.cameras.size() == 2;
  const bool has_samples = outcome_ && outcome_->collector && !outcome_->collector->samples().empty();
  start_->setEnabled(!busy && has_cameras);
  load_->setEnabled(!busy);
  amplitude_->setEnabled(!busy);
  cancel_button_->setEnabled(busy);
  delete_->setEnabled(!busy && has_samples);
  outliers_->setEnabled(!busy && has_samples);
  save_->setEnabled(!busy && outcome_ && outcome_->done && outcome_->calibration.has_value());
}

void HandEyePanel::start() {
  if (running() || options_.cameras.cameras.size() != 2) return;
  calibration::HandEyeProcedureOptions o = options_;
  o.pattern_amplitude_deg = amplitude_->value();
  o.cancel = worker_.cancelFlag();
  o.log = calibrationLogSink(this, log_);
  o.progress = [this](const calibration::HandEyeProgress& p) {
    std::optional<calibration::HandEyeCollector> copy;
    if (p.collector != nullptr) copy = *p.collector;
    QMetaObject::invokeMethod(
        this,
        [this, copy = std::move(copy), check = p.check, stills = p.stills, verdict = QString::fromStdString(p.verdict)] {
          if (copy) showCollector(*copy);
          status_->setText(QString("still %1: %2 · %3 samples kept · %4")
                               .arg(stills)
                               .arg(verdict.toHtmlEscaped())
                               .arg(copy ? int(copy->samples().size()) : 0)
                               .arg(QString::fromStdString(check.describe()).toHtmlEscaped()));
        },
        Qt::QueuedConnection);
  };
  outcome_.reset();
  resolve_what_.clear();
  log_->clear();
  samples_->setRowCount(0);
  setBusy(true);
  status_->setText("starting: the head moves along the pattern…");
  const link::LinkEndpoints endpoints = endpoints_;
  worker_.launch(
      [o, endpoints] {
        link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false});
        calibration::CalibrationRobot robot(client, "hand-eye wizard (console)");
        return calibration::runHandEyeAuto(robot, o);
      },
      [this] { onFinished(); });
}

void HandEyePanel::cancel() { worker_.cancel(); }

void HandEyePanel::onFinished() {
  outcome_ = worker_.take();
  if (!outcome_) return;
  if (outcome_->collector) showCollector(*outcome_->collector);
  char buf[200];
  std::snprintf(buf, sizeof buf, "%d stills, %d refused, %d too close, %d outliers removed", outcome_->stills,
                outcome_->refused, outcome_->too_close, outcome_->outliers_removed);
  if (!resolve_what_.isEmpty()) {
    status_->setText(QString("%1 solved in %2 ms: %3")
                         .arg(resolve_what_)
                         .arg(last_resolve_ms_, 0, 'f', 0)
                         .arg(QString::fromStdString(outcome_->done ? "done" : outcome_->error).toHtmlEscaped()));
    resolve_what_.clear();
  } else if (outcome_->done) {
    status_->setText(QString("<b>Done</b> in %1 s from the first sample (%2).").arg(outcome_->first_sample_to_result_s, 0, 'f', 1).arg(buf));
  } else {
    status_->setText("<span style='color:#b00'><b>Not done:</b> " + QString::fromStdString(outcome_->error).toHtmlEscaped() +
                     "</span> (" + buf + ")");
  }
  setBusy(false);
  emit runFinished(outcome_->done);
}

void HandEyePanel::resolve(const QString& what) {
  // In the worker like a run (0.5 s for 28 samples under ASan, tens of ms in Release): the
  // window never waits on a solve.
  calibration::HandEyeOutcome base = std::move(*outcome_);
  outcome_.reset();
  setBusy(true);
  status_->setText(what + " solving…");
  resolve_what_ = what;
  const calib::SystemCalibration cameras = options_.cameras;
  worker_.launch(
      [this, base = std::move(base), cameras]() mutable {
        const auto t0 = std::chrono::steady_clock::now();
        std::string error;
        const bool ok = base.collector->solve(&error);
        last_resolve_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        calibration::takeSolve(base, cameras, ok, error);
        return std::move(base);
      },
      [this] { onFinished(); });
}

void HandEyePanel::deleteSample(int index) {
  if (running() || !outcome_ || !outcome_->collector || index < 0 || index >= int(outcome_->collector->samples().size()))
    return;
  outcome_->collector->remove(std::size_t(index));
  resolve(QString("without sample %1,").arg(index + 1));
}

void HandEyePanel::removeOutliers() {
  if (running() || !outcome_ || !outcome_->collector) return;
  const int removed = outcome_->collector->removeOutliers();
  outcome_->outliers_removed += removed;
  resolve(QString("%1 outlier(s) removed,").arg(removed));
}

bool HandEyePanel::saveTo(const QString& path, const QString& format, QString* error) {
  if (!outcome_ || !outcome_->done || !outcome_->calibration) {
    *error = "no hand-eye result that meets the done rule";
    return false;
  }
  if (!saveCalibrationAs(*outcome_->calibration, path, format, error)) return false;
  log_->appendPlainText("saved " + path);
  return true;
}

void HandEyePanel::showCollector(const calibration::HandEyeCollector& collector) {
  const auto& samples = collector.samples();
  const std::vector<double> rms = collector.sampleRmsPx();
  const std::vector<bool> outliers = collector.outliers();
  const calib::HandEyeIdentifiability d = collector.diversity();
  setMeter(head_spread_, "head", d.head_axis_spread_deg, collector.options().rule.min_axis_spread_deg);
  setMeter(wrist_spread_, "wrist", d.wrist_axis_spread_deg, collector.options().rule.min_axis_spread_deg);

  samples_->setRowCount(int(samples.size()));
  const auto angleTo = [](const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
  };
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const calib::HandEyeSample& s = samples[i].sample;
    const QString seen = QString(s.corners_l ? "L" : "") + (s.corners_r ? "R" : "");
    const QStringList cells{seen, QString::number(angleTo(samples[0].sample.T_robot_flange, s.T_robot_flange), 'f', 1),
                            QString::number(angleTo(samples[0].sample.T_mount_wrist, s.T_mount_wrist), 'f', 1),
                            std::isfinite(rms[i]) ? QString::number(rms[i], 'f', 3) : "—",
                            outliers[i] ? "outlier" : ""};
    for (int col = 0; col < cells.size(); ++col) {
      auto* item = new QTableWidgetItem(cells[col]);
      if (outliers[i]) item->setBackground(QColor(255, 200, 200));
      samples_->setItem(int(i), col, item);
    }
  }

  const auto& result = collector.result();
  results_->clearContents();
  if (result) {
    const std::array<Eigen::Isometry3d, 3> T{result->T_flange_cam_l, result->T_robot_mount, result->T_wrist_marker};
    for (int k = 0; k < 3; ++k) {
      const Eigen::AngleAxisd aa(T[std::size_t(k)].linear());
      const calib::PoseStddev& sd = result->stddev[std::size_t(k)];
      const QStringList cells{vectorText(T[std::size_t(k)].translation() * 1e3, 1),
                              sd.valid ? vectorText(sd.translation_m * 1e3, 2) : "—",
                              vectorText(aa.axis() * aa.angle() * 180.0 / M_PI, 2),
                              sd.valid ? vectorText(sd.rotation_deg, 3) : "—"};
      for (int col = 0; col < 4; ++col) results_->setItem(k, col, new QTableWidgetItem(cells[col]));
    }
  }

  plot_->clearPlottables();
  auto* inliers = new QCPBars(plot_->xAxis, plot_->yAxis);
  inliers->setName("sample RMS (px)");
  inliers->setBrush(QColor(70, 120, 200));
  inliers->setPen(Qt::NoPen);
  auto* marked = new QCPBars(plot_->xAxis, plot_->yAxis);
  marked->setName("outlier");
  marked->setBrush(QColor(210, 50, 50));
  marked->setPen(Qt::NoPen);
  double top = 0.5;
  for (std::size_t i = 0; i < rms.size(); ++i) {
    if (!std::isfinite(rms[i])) continue;
    (outliers[i] ? marked : inliers)->addData(double(i + 1), rms[i]);
    top = std::max(top, rms[i]);
  }
  const double bound = collector.outlierBoundPx();
  if (std::isfinite(bound)) {
    auto* line = plot_->addGraph();
    line->setName(QString("outlier bound %1 px").arg(bound, 0, 'f', 2));
    line->setPen(QPen(QColor(210, 50, 50), 1.5, Qt::DashLine));
    line->addData(0.5, bound);
    line->addData(double(rms.size()) + 0.5, bound);
    top = std::max(top, bound);
  }
  plot_->xAxis->setRange(0.5, std::max<double>(5.0, double(rms.size())) + 0.5);
  plot_->yAxis->setRange(0, top * 1.15);
  plot_->replot();
}

}  // namespace telesphere::console
