// SPDX-License-Identifier: MIT
/// @brief The console's Hand-eye panel (issue #15, paper §III-B eqs. 1–3): the head runs the
///        sinusoidal pattern while the manipulator moves its wrist marker in view; stills become
///        samples in a worker thread (console/calibration/hand_eye_procedure.h), with
///          - the rotation-diversity meter (how far the head's and the wrist's rotation axes
///            spread, against the bound the solve needs),
///          - a solve from 5 samples on and again on every new one, the three transforms with
///            their standard deviations,
///          - per-sample residuals (table and bar plot) with outliers marked; delete any sample
///            or all outliers and the result is solved again (in the worker),
///          - the done rule with its numbers, and save as our file, kalibr or Basalt (only a
///            result that meets the rule).
///        The cameras' intrinsics and T_cam_l_cam_r come from a calibration file (Load…), e.g.
///        the Calibration panel's result. The panel talks to the robot through its own link client;
///        the worker, cancel, log and save are the wizards' shared scaffolding
///        (calibration_wizard_worker.h, calibration_save_dialog.h).
#pragma once

#include <QWidget>
#include <atomic>
#include <optional>

#include "console/calibration/hand_eye_procedure.h"
#include "console/widgets/calibration_wizard_worker.h"
#include "robot/link/link_endpoints.h"

class QCustomPlot;
class QDoubleSpinBox;
class QLabel;
class QPlainTextEdit;
class QProgressBar;
class QPushButton;
class QTableWidget;

namespace telesphere::console {

class HandEyePanel : public QWidget {
  Q_OBJECT

 public:
  explicit HandEyePanel(const link::LinkEndpoints& endpoints, QWidget* parent = nullptr);
  ~HandEyePanel() override;  ///< cancels a run and waits for its worker

  /// Cameras, marker, rule and limits of the next run (the amplitude comes from the panel).
  void setProcedureOptions(const calibration::HandEyeProcedureOptions& options);
  /// The intrinsics and T_cam_l_cam_r to hold fixed, from a calibration file.
  bool loadCameras(const QString& path, QString* error);

  /// The buttons' actions (tests call them as a click would).
  void start();
  void cancel();
  void deleteSample(int index);  ///< then solves again (worker)
  void removeOutliers();         ///< then solves again (worker)
  bool saveTo(const QString& path, const QString& format, QString* error);

  bool running() const { return worker_.running(); }
  QString statusText() const;
  const std::optional<calibration::HandEyeOutcome>& outcome() const { return outcome_; }
  /// Wall time of the last solve after a delete, ms.
  double lastResolveMs() const { return last_resolve_ms_; }

 signals:
  void runFinished(bool done);

 private:
  void setBusy(bool busy);
  void onFinished();
  void showCollector(const calibration::HandEyeCollector& collector);
  void resolve(const QString& what);

  link::LinkEndpoints endpoints_;
  calibration::HandEyeProcedureOptions options_;
  QString cameras_path_;
  CalibrationWizardWorker<calibration::HandEyeOutcome> worker_{this};
  std::optional<calibration::HandEyeOutcome> outcome_;
  std::atomic<double> last_resolve_ms_{0};
  QString resolve_what_;  ///< set while a delete's solve runs

  QLabel* rule_ = nullptr;
  QLabel* cameras_ = nullptr;
  QDoubleSpinBox* amplitude_ = nullptr;
  QPushButton* load_ = nullptr;
  QPushButton* start_ = nullptr;
  QPushButton* cancel_button_ = nullptr;
  QPushButton* delete_ = nullptr;
  QPushButton* outliers_ = nullptr;
  QPushButton* save_ = nullptr;
  QProgressBar* head_spread_ = nullptr;
  QProgressBar* wrist_spread_ = nullptr;
  QLabel* status_ = nullptr;
  QTableWidget* samples_ = nullptr;
  QTableWidget* results_ = nullptr;
  QCustomPlot* plot_ = nullptr;
  QPlainTextEdit* log_ = nullptr;
};

}  // namespace telesphere::console
