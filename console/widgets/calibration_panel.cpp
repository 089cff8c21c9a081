// SPDX-License-Identifier: MIT
/// @brief CalibrationPanel (see calibration_panel.h).
#include "console/widgets/calibration_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QListWidget>
#include <QMetaObject>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QTabWidget>
#include <QTableWidget>
#include <QVBoxLayout>

#include "calib/calibration_file.h"
#include "console/widgets/calibration_pictures.h"
#include "console/widgets/calibration_save_dialog.h"
#include "console/widgets/calibration_residuals_view.h"
#include "robot/link/link_client.h"

namespace telesphere::console {

CalibrationPanel::CalibrationPanel(const link::LinkEndpoints& endpoints, QWidget* parent)
    : QWidget(parent), endpoints_(endpoints) {
  auto* layout = new QVBoxLayout(this);
  auto* title = new QLabel("<b>Intrinsics and stereo</b> — fix an Aprilgrid about 1 m in front of the head; "
                           "the robot turns the head so that it covers both images out to the rim.");
  title->setWordWrap(true);
  layout->addWidget(title);
  rule_ = new QLabel;
  rule_->setWordWrap(true);
  rule_->setObjectName("calibration_rule");
  layout->addWidget(rule_);

  auto* row = new QHBoxLayout;
  model_ = new QComboBox;
  model_->addItems({"ds", "eucm", "kb4", "pinhole"});
  model_->setObjectName("calibration_model");
  model_->setToolTip("camera model to solve for");
  auto_ = new QPushButton("Auto-calibrate");
  auto_->setObjectName("calibration_auto");
  cancel_button_ = new QPushButton("Cancel");
  cancel_button_->setObjectName("calibration_cancel");
  delete_ = new QPushButton("Delete sample");
  delete_->setObjectName("calibration_delete");
  live_button_ = new QPushButton("Live view");
  live_button_->setObjectName("calibration_live");
  live_button_->setToolTip("stills from both cameras one after another, with the corners found and the gates' "
                           "verdict; for a board held by hand (Cancel stops it)");
  capture_ = new QPushButton("Capture");
  capture_->setObjectName("calibration_capture");
  capture_->setToolTip("keep the next live still that passes the gates (board still, enough corners, a new view)");
  auto_capture_ = new QCheckBox("auto-capture");
  auto_capture_->setObjectName("calibration_auto_capture");
  auto_capture_->setChecked(true);
  auto_capture_->setToolTip("keep every live still that passes the gates");
  solve_ = new QPushButton("Solve");
  solve_->setObjectName("calibration_solve");
  solve_->setToolTip("solve the kept samples and check the done rule");
  compare_ = new QPushButton("Compare models");
  compare_->setObjectName("calibration_compare");
  compare_->setToolTip("solve the kept samples with ds, eucm, kb4 and pinhole; preselect the simplest whose RMS is "
                       "within the tolerance");
  tolerance_ = new QDoubleSpinBox;
  tolerance_->setObjectName("calibration_tolerance");
  tolerance_->setRange(0.05, 10.0);
  tolerance_->setSingleStep(0.05);
  tolerance_->setDecimals(2);
  tolerance_->setValue(1.0);
  tolerance_->setSuffix(" px");
  tolerance_->setToolTip("the RMS a camera model must reach to be preselected");
  save_ = new QPushButton("Save as…");
  save_->setObjectName("calibration_save");
  row->addWidget(new QLabel("Model"));
  row->addWidget(model_);
  row->addWidget(auto_);
  row->addWidget(cancel_button_);
  row->addWidget(live_button_);
  row->addWidget(capture_);
  row->addWidget(auto_capture_);
  row->addWidget(solve_);
  row->addStretch(1);
  row->addWidget(compare_);
  row->addWidget(tolerance_);
  row->addWidget(delete_);
  row->addWidget(save_);
  layout->addLayout(row);

  progress_ = new QProgressBar;
  progress_->setFormat("%v of %m samples");
  layout->addWidget(progress_);
  status_ = new QLabel("No calibration run yet.");
  status_->setObjectName("calibration_status");
  status_->setWordWrap(true);
  layout->addWidget(status_);

  coverage_ = new QLabel;
  coverage_->setObjectName("calibration_coverage");
  coverage_->setToolTip("polar-angle bins: green reached, red required and missing, grey optional");
  layout->addWidget(coverage_);
  auto* tabs = tabs_ = new QTabWidget;
  tabs->setObjectName("calibration_tabs");
  samples_ = new QListWidget;
  samples_->setObjectName("calibration_samples");
  samples_->setViewMode(QListView::IconMode);
  samples_->setIconSize(QSize(324, 90));
  samples_->setResizeMode(QListView::Adjust);
  samples_->setMovement(QListView::Static);
  samples_->setSpacing(4);
  tabs->addTab(samples_, "Samples");
  results_ = new QTableWidget(0, 3);
  results_->setObjectName("calibration_results");
  results_->setHorizontalHeaderLabels({"parameter", "cam_l", "cam_r"});
  results_->horizontalHeader()->setStretchLastSection(true);
  results_->verticalHeader()->hide();
  models_ = new QTableWidget(0, 5);
  models_->setObjectName("calibration_models");
  models_->setHorizontalHeaderLabels({"model", "parameters", "RMS px (worse camera)", "solve s", "note"});
  models_->horizontalHeader()->setStretchLastSection(true);
  models_->verticalHeader()->hide();
  auto* results_page = new QWidget;
  auto* results_layout = new QVBoxLayout(results_page);
  results_layout->setContentsMargins(0, 0, 0, 0);
  results_layout->addWidget(results_, 3);
  results_layout->addWidget(new QLabel("<b>Camera models on the same samples</b> (Compare models)"));
  results_layout->addWidget(models_, 1);
  tabs->addTab(results_page, "Results");
  residuals_ = new CalibrationResidualsView;
  residuals_->setObjectName("calibration_residuals");
  tabs->addTab(residuals_, "Residuals");
  auto* live_page = new QWidget;
  auto* live_layout = new QVBoxLayout(live_page);
  live_image_ = new QLabel("Live view off.");
  live_image_->setObjectName("calibration_live_image");
  live_image_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
  live_status_ = new QLabel;
  live_status_->setObjectName("calibration_live_status");
  live_status_->setWordWrap(true);
  live_layout->addWidget(live_image_);
  live_layout->addWidget(live_status_);
  live_layout->addStretch(1);
  tabs->addTab(live_page, "Live");
  log_ = newCalibrationLog("calibration_log");
  tabs->addTab(log_, "Log");
  layout->addWidget(tabs, 1);

  connect(auto_, &QPushButton::clicked, this, &CalibrationPanel::startAuto);
  connect(cancel_button_, &QPushButton::clicked, this, &CalibrationPanel::cancel);
  connect(live_button_, &QPushButton::clicked, this, &CalibrationPanel::startLive);
  connect(capture_, &QPushButton::clicked, this, &CalibrationPanel::requestCapture);
  connect(solve_, &QPushButton::clicked, this, &CalibrationPanel::solve);
  connect(compare_, &QPushButton::clicked, this, &CalibrationPanel::compareModels);
  connect(auto_capture_, &QCheckBox::toggled, this, [this](bool on) { live_auto_capture_ = on; });
  connect(delete_, &QPushButton::clicked, this, [this] {
    if (samples_->currentRow() >= 0) deleteSample(samples_->currentRow());
  });
  connectCalibrationSave(save_, this, status_,
                         [this](const QString& path, const QString& format, QString* error) { return saveTo(path, format, error); });
  setProcedureOptions({});
  setBusy(false);
}

CalibrationPanel::~CalibrationPanel() { worker_.stop(); }

void CalibrationPanel::setProcedureOptions(const calibration::IntrinsicsProcedureOptions& options) {
  options_ = options;
  rule_->setText("<b>Done when:</b> " + QString::fromStdString(options_.rule.describe(options_.coverage.polar_bin_deg)));
  progress_->setRange(0, options_.rule.min_views);
}

void CalibrationPanel::setBusy(bool busy) {
  auto_->setEnabled(!busy);
  model_->setEnabled(!busy);
  cancel_button_->setEnabled(busy);
  live_button_->setEnabled(!busy);
  capture_->setEnabled(busy && live_running_);
  solve_->setEnabled(!busy && outcome_ && outcome_->collector && !outcome_->collector->samples().empty());
  compare_->setEnabled(solve_->isEnabled());
  delete_->setEnabled(!busy && outcome_ && outcome_->collector && !outcome_->collector->samples().empty());
  save_->setEnabled(!busy && outcome_ && outcome_->done && outcome_->calibration.has_value());
}

void CalibrationPanel::launch(std::function<calibration::IntrinsicsOutcome()> work, const QString& what) {
  setBusy(true);
  status_->setText(what);
  worker_.launch(std::move(work), [this] { onFinished(); });
}

void CalibrationPanel::startAuto() {
  if (running()) return;
  calibration::IntrinsicsProcedureOptions o = options_;
  o.model = model_->currentText().toStdString();
  o.cancel = worker_.cancelFlag();
  o.log = calibrationLogSink(this, log_);
  o.progress = [this](const calibration::IntrinsicsProgress& p) {
    QImage thumb = p.last_kept ? sampleImage(*p.last_kept) : QImage();
    QMetaObject::invokeMethod(
        this,
        [this, p_stage = QString::fromStdString(p.stage), samples = p.samples, visited = p.poses_visited,
         planned = p.poses_planned, thumb] {
          progress_->setValue(std::min(samples, progress_->maximum()));
          status_->setText(QString("%1: %2 samples kept, %3 of %4 head poses visited").arg(p_stage).arg(samples).arg(visited).arg(planned));
          if (!thumb.isNull()) samples_->addItem(new QListWidgetItem(QIcon(QPixmap::fromImage(thumb)), QString::number(samples)));
        },
        Qt::QueuedConnection);
  };
  samples_->clear();
  results_->setRowCount(0);
  residuals_->clear();
  comparison_.reset();
  log_->clear();
  outcome_.reset();
  const link::LinkEndpoints endpoints = endpoints_;
  launch(
      [o, endpoints] {
        link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false});
        calibration::CalibrationRobot robot(client, "intrinsics wizard (console)");
        return calibration::runIntrinsicsAuto(robot, o);
      },
      "starting: holding the head and looking for the board…");
}

void CalibrationPanel::cancel() { worker_.cancel(); }

void CalibrationPanel::deleteSample(int index) {
  if (running() || !outcome_ || !outcome_->collector || index < 0 ||
      index >= int(outcome_->collector->samples().size())) {
    return;
  }
  calibration::IntrinsicsCollector collector = *outcome_->collector;
  collector.remove(std::size_t(index));
  delete samples_->takeItem(index);
  for (int i = 0; i < samples_->count(); ++i) samples_->item(i)->setText(QString::number(i + 1));
  comparison_.reset();  // of other samples
  resolve(std::move(collector), QString("solving again without sample %1…").arg(index + 1));
}

void CalibrationPanel::solve() {
  if (running() || !outcome_ || !outcome_->collector || outcome_->collector->samples().empty()) return;
  resolve(*outcome_->collector, QString("solving %1 samples…").arg(outcome_->collector->samples().size()));
}

void CalibrationPanel::compareModels() {
  if (running() || !outcome_ || !outcome_->collector || outcome_->collector->samples().empty()) return;
  const calib::AprilGrid grid = options_.grid;
  const double tolerance = tolerance_->value();
  calibration::IntrinsicsOutcome base = *outcome_;
  launch(
      [this, grid, tolerance, base] {
        auto comparison = calibration::compareModels(*base.collector, grid, tolerance);
        {
          std::lock_guard lock(comparison_mutex_);
          pending_comparison_ = std::move(comparison);
        }
        return base;
      },
      QString("solving %1 samples with each camera model…").arg(outcome_->collector->samples().size()));
}

void CalibrationPanel::resolve(calibration::IntrinsicsCollector collector, const QString& what) {
  calibration::IntrinsicsProcedureOptions o = options_;
  o.model = model_->currentText().toStdString();
  o.log = calibrationLogSink(this, log_);
  calibration::IntrinsicsOutcome base = *outcome_;
  launch(
      [o, collector = std::move(collector), base]() mutable {
        calibration::solveCollected(std::move(collector), o, base);
        return base;
      },
      what);
}

void CalibrationPanel::startLive() {
  if (running()) return;
  calibration::IntrinsicsProcedureOptions o = options_;
  o.model = model_->currentText().toStdString();
  std::optional<calibration::IntrinsicsCollector> start;
  if (outcome_ && outcome_->collector) start = outcome_->collector;  // go on from the samples shown
  if (!start) samples_->clear();
  comparison_.reset();
  live_running_ = true;
  live_capture_request_ = false;
  capture_waiting_ = false;
  live_auto_capture_ = auto_capture_->isChecked();
  live_stills_ = 0;
  tabs_->setCurrentWidget(live_image_->parentWidget());
  const link::LinkEndpoints endpoints = endpoints_;
  launch(
      [this, o, endpoints, start] {
        link::LinkClient client(endpoints, link::LinkClient::Options{.frames = false});
        calibration::CalibrationRobot robot(client, "intrinsics wizard, live capture (console)");
        calibration::LiveCapture live(robot, o);
        if (start) live.setCollector(*start);
        std::string last_error;
        while (!worker_.cancelled()) {
          if (live_capture_request_.exchange(false)) live.requestCapture();
          live.setAutoCapture(live_auto_capture_);
          std::string error;
          auto still = live.step(&error);
          if (!still) {
            if (error != last_error) {
              QMetaObject::invokeMethod(this, [this, text = QString::fromStdString("live: " + error)] {
                live_status_->setText(text);
                log_->appendPlainText(text);
              }, Qt::QueuedConnection);
            }
            last_error = error;
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            continue;
          }
          last_error.clear();
          QMetaObject::invokeMethod(this, [this, s = std::move(*still)] { showLiveStill(s); }, Qt::QueuedConnection);
        }
        calibration::IntrinsicsOutcome out;
        out.stills = live.stills();
        out.collector = live.takeCollector();
        const int kept = out.collector ? int(out.collector->samples().size()) : 0;
        out.error = "live view stopped with " + std::to_string(kept) + " samples kept: Solve to calibrate them";
        return out;
      },
      "live view: stills from both cameras…");
}

void CalibrationPanel::requestCapture() {
  if (!live()) return;
  live_capture_request_ = true;
  capture_waiting_ = true;
  live_status_->setText(live_status_->text() + " · capture requested: the next still that passes is kept");
}

void CalibrationPanel::showLiveStill(const calibration::LiveStill& still) {
  ++live_stills_;
  live_image_->setPixmap(QPixmap::fromImage(liveImage(still)));
  QString text = QString("still %1 · ").arg(live_stills_);
  if (still.kept) {
    text += QString("<span style='color:#060'><b>kept</b></span> as sample %1").arg(still.samples);
    samples_->addItem(new QListWidgetItem(QIcon(QPixmap::fromImage(sampleImage(still.sample))), QString::number(still.samples)));
    progress_->setValue(std::min(still.samples, progress_->maximum()));
  } else {
    text += QString("not kept (%1 samples so far): ").arg(still.samples) +
            QString::fromStdString(still.verdict.reason).toHtmlEscaped();
  }
  // A request made while this still was being taken reaches the worker at its next still, so
  // the panel's own flag says whether one waits; a kept still ends it.
  if (still.kept) capture_waiting_ = false;
  if (capture_waiting_ || still.capture_pending) text += " · capture requested: the next still that passes is kept";
  live_status_->setText(text);
}

QString CalibrationPanel::liveStatusText() const { return live_status_->text(); }

void CalibrationPanel::onFinished() {
  outcome_ = worker_.take();
  live_running_ = false;
  bool fresh_comparison = false;
  {
    std::lock_guard lock(comparison_mutex_);
    fresh_comparison = pending_comparison_.has_value();
    if (pending_comparison_) comparison_ = std::move(pending_comparison_);
    pending_comparison_.reset();
  }
  if (fresh_comparison && comparison_ && comparison_->preselected)
    model_->setCurrentText(QString::fromStdString(*comparison_->preselected));
  showOutcome();
  setBusy(false);
  emit runFinished(outcome_ && outcome_->done);
}

void CalibrationPanel::showOutcome() {
  if (!outcome_) return;
  const calibration::IntrinsicsOutcome& o = *outcome_;
  if (o.done) {
    status_->setText(QString("<span style='color:#060'><b>Done</b></span>: %1 samples, RMS %2 / %3 px, "
                             "%4 s from the first sample to the result.")
                         .arg(o.collector ? int(o.collector->samples().size()) : 0)
                         .arg(o.result->cameras[0].rms_px, 0, 'f', 3)
                         .arg(o.result->cameras[1].rms_px, 0, 'f', 3)
                         .arg(o.first_sample_to_result_s, 0, 'f', 1));
  } else {
    status_->setText("<span style='color:#b00'><b>Not done</b></span>: " + QString::fromStdString(o.error).toHtmlEscaped() +
                     (o.result ? " — the result below is shown, not confident." : ""));
  }
  if (o.collector) progress_->setValue(std::min(int(o.collector->samples().size()), progress_->maximum()));
  showCoverage();
  showComparison();
  results_->setRowCount(0);
  residuals_->clear();
  if (!o.result) return;
  residuals_->showResult(*o.result, o.collector ? &*o.collector : nullptr);
  const auto names = calib::GenericCamera::paramNames(o.result->cameras[0].calibration.camera.modelName());
  const auto add = [&](const QString& name, const QString& l, const QString& r) {
    const int row = results_->rowCount();
    results_->insertRow(row);
    results_->setItem(row, 0, new QTableWidgetItem(name));
    results_->setItem(row, 1, new QTableWidgetItem(l));
    results_->setItem(row, 2, new QTableWidgetItem(r));
  };
  const auto cell = [&](int c, std::size_t i) {
    const calib::CameraIntrinsicResult& cam = o.result->cameras[std::size_t(c)];
    const double v = cam.calibration.camera.params()[Eigen::Index(i)];
    return i < cam.param_stddev.size() ? QString("%1 ± %2").arg(v, 0, 'f', 4).arg(cam.param_stddev[i], 0, 'g', 2)
                                       : QString::number(v, 'f', 4);
  };
  for (std::size_t i = 0; i < names.size(); ++i) add(QString::fromUtf8(names[i].data(), int(names[i].size())), cell(0, i), cell(1, i));
  add("RMS px", QString::number(o.result->cameras[0].rms_px, 'f', 3), QString::number(o.result->cameras[1].rms_px, 'f', 3));
  add("views", QString::number(o.result->cameras[0].views_used), QString::number(o.result->cameras[1].views_used));
  if (o.result->T_cam_l_cam_r) {
    const Eigen::Vector3d t = o.result->T_cam_l_cam_r->translation() * 1000.0;
    const Eigen::AngleAxisd r(o.result->T_cam_l_cam_r->linear());
    const calib::PoseStddev& sd = o.result->T_cam_l_cam_r_stddev;
    const Eigen::Vector3d st = sd.translation_m * 1000.0;
    add("T_cam_l_cam_r",
        QString("t = (%1, %2, %3) mm").arg(t.x(), 0, 'f', 2).arg(t.y(), 0, 'f', 2).arg(t.z(), 0, 'f', 2) +
            (sd.valid ? QString(" ± (%1, %2, %3)").arg(st.x(), 0, 'f', 2).arg(st.y(), 0, 'f', 2).arg(st.z(), 0, 'f', 2) : QString()),
        QString("rotation %1°").arg(r.angle() * 180.0 / M_PI, 0, 'f', 3) +
            (sd.valid ? QString(" ± %1° (worst axis)").arg(sd.rotation_deg.maxCoeff(), 0, 'f', 4) : QString()));
  }
  results_->resizeColumnsToContents();
}

void CalibrationPanel::showComparison() {
  models_->setRowCount(0);
  if (!comparison_) return;
  for (const calibration::ModelFit& fit : comparison_->fits) {
    const int row = models_->rowCount();
    models_->insertRow(row);
    const bool chosen = comparison_->preselected && *comparison_->preselected == fit.model;
    const QString note = !fit.ok              ? QString::fromStdString(fit.message)
                         : !fit.message.empty() ? QString::fromStdString(fit.message)
                         : chosen               ? QString("preselected: the simplest within %1 px").arg(comparison_->tolerance_px, 0, 'f', 2)
                         : fit.rms_px > comparison_->tolerance_px ? QString("above the tolerance")
                                                                  : QString();
    const QStringList cells{QString::fromStdString(fit.model), QString::number(fit.parameters),
                            fit.ok ? QString::number(fit.rms_px, 'f', 3) : QString("—"),
                            QString::number(fit.solve_s, 'f', 1), note};
    for (int c = 0; c < cells.size(); ++c) {
      auto* item = new QTableWidgetItem(cells[c]);
      if (chosen) {
        QFont f = item->font();
        f.setBold(true);
        item->setFont(f);
      }
      models_->setItem(row, c, item);
    }
  }
  if (!comparison_->preselected) {
    const int row = models_->rowCount();
    models_->insertRow(row);
    models_->setItem(row, 0, new QTableWidgetItem(QString("no model within %1 px").arg(comparison_->tolerance_px, 0, 'f', 2)));
  }
  models_->resizeColumnsToContents();
}

void CalibrationPanel::showCoverage() {
  if (!outcome_ || !outcome_->collector) {
    coverage_->clear();
    return;
  }
  coverage_->setPixmap(coveragePicture(*outcome_->collector, calibration::ruleInEffect(options_.rule, *outcome_->collector)));
  coverage_->setToolTip(QString::fromStdString("cam_l: " + outcome_->collector->coverage(0).describe() +
                                               "\ncam_r: " + outcome_->collector->coverage(1).describe()));
}

bool CalibrationPanel::saveTo(const QString& path, const QString& format, QString* error) {
  if (!outcome_ || !outcome_->calibration) {
    *error = "nothing to save: no calibration result yet";
    return false;
  }
  if (!outcome_->done) {
    *error = "the done rule is not met: a result that is not confident is not saved (" +
             QString::fromStdString(outcome_->error) + ")";
    return false;
  }
  if (!saveCalibrationAs(*outcome_->calibration, path, format, error)) return false;
  status_->setText(status_->text() + "<br>Saved " + path.toHtmlEscaped() + " (" + format + ").");
  return true;
}

QString CalibrationPanel::statusText() const { return status_->text(); }

int CalibrationPanel::sampleCount() const {
  return outcome_ && outcome_->collector ? int(outcome_->collector->samples().size()) : samples_->count();
}

}  // namespace telesphere::console
