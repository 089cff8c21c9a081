// SPDX-License-Identifier: MIT
/// @brief The console's Calibration panel (issue #15, paper §III-B): the intrinsic and stereo
///        calibration on the live robot, run in a worker thread with progress and cancel (the
///        window never waits on it), the done rule stated with its numbers, the kept samples
///        as thumbnails with their corners (delete any, then solve again), coverage per camera
///        in polar bins, every parameter with its standard deviation, the residuals against polar
///        angle and the worst views (console/widgets/calibration_residuals_view.h), and save as our file,
///        kalibr camchain or Basalt JSON (only a result that meets the done rule). The procedure is console/calibration/intrinsics_procedure.h;
///        the panel talks to the robot through its own link client; the worker, cancel, log and
///        save are the wizards' shared scaffolding (calibration_wizard_worker.h,
///        calibration_save_dialog.h), the pictures calibration_pictures.h.
///
/// Compare models solves the samples with every camera model and preselects the simplest within
/// the tolerance (console/calibration/model_comparison.h).
/// The live view (console/calibration/live_capture.h): full-resolution stills one after another
/// with their corners and the gates' verdict, kept automatically or on Capture, for a board held
/// by hand; then Solve.
///
/// Hand-eye is the Hand-eye panel's (console/widgets/hand_eye_panel.h). Not here yet (issue #15 stays
/// open): applying a result to the running robot and XR app.
#pragma once

#include <QWidget>
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>

#include "console/calibration/intrinsics_procedure.h"
#include "console/calibration/live_capture.h"
#include "console/calibration/model_comparison.h"
#include "console/widgets/calibration_wizard_worker.h"
#include "robot/link/link_endpoints.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QListWidget;
class QPlainTextEdit;
class QProgressBar;
class QPushButton;
class QTabWidget;
class QTableWidget;

namespace telesphere::console {

class CalibrationResidualsView;

class CalibrationPanel : public QWidget {
  Q_OBJECT

 public:
  explicit CalibrationPanel(const link::LinkEndpoints& endpoints, QWidget* parent = nullptr);
  ~CalibrationPanel() override;  ///< cancels a run and waits for its worker

  /// Options of the next run (grid, done rule, initial calibration…); the model comes from the
  /// panel's selector.
  void setProcedureOptions(const calibration::IntrinsicsProcedureOptions& options);

  /// The buttons' actions (tests call them as a click would).
  void startAuto();
  /// The live view: stills one after another with their corners and the gates' verdict, kept
  /// automatically when the gates pass (auto-capture) or on Capture; stopped by cancel().
  void startLive();
  void requestCapture();         ///< keep the next live still that passes the gates
  void cancel();
  void deleteSample(int index);  ///< then solves again in the worker
  void solve();                  ///< solves the kept samples (after a live view) in the worker
  /// Solves the kept samples with every camera model (worker), lists their RMS and preselects
  /// the simplest within the tolerance in the model selector.
  void compareModels();
  const std::optional<calibration::ModelComparison>& comparison() const { return comparison_; }
  bool saveTo(const QString& path, const QString& format, QString* error);

  bool running() const { return worker_.running(); }
  bool live() const { return running() && live_running_; }
  int liveStills() const { return live_stills_; }  ///< shown since the live view started
  QString liveStatusText() const;
  QString statusText() const;
  int sampleCount() const;
  const std::optional<calibration::IntrinsicsOutcome>& outcome() const { return outcome_; }

 signals:
  void runFinished(bool done);

 private:
  void launch(std::function<calibration::IntrinsicsOutcome()> work, const QString& what);
  void onFinished();
  void showOutcome();
  void showCoverage();
  void showComparison();
  void setBusy(bool busy);
  void resolve(calibration::IntrinsicsCollector collector, const QString& what);
  void showLiveStill(const calibration::LiveStill& still);

  link::LinkEndpoints endpoints_;
  calibration::IntrinsicsProcedureOptions options_;
  CalibrationWizardWorker<calibration::IntrinsicsOutcome> worker_{this};
  std::atomic<bool> live_running_{false};
  std::atomic<bool> live_auto_capture_{true};
  std::atomic<bool> live_capture_request_{false};
  int live_stills_ = 0;
  bool capture_waiting_ = false;  ///< Capture clicked, no still kept since (GUI thread)
  std::optional<calibration::IntrinsicsOutcome> outcome_;
  std::mutex comparison_mutex_;  ///< guards pending_comparison_ (written by the worker)
  std::optional<calibration::ModelComparison> comparison_;  ///< of the samples in outcome_
  std::optional<calibration::ModelComparison> pending_comparison_;

  QLabel* rule_ = nullptr;
  QComboBox* model_ = nullptr;
  QPushButton* auto_ = nullptr;
  QPushButton* cancel_button_ = nullptr;
  QPushButton* live_button_ = nullptr;
  QPushButton* capture_ = nullptr;
  QCheckBox* auto_capture_ = nullptr;
  QPushButton* solve_ = nullptr;
  QPushButton* compare_ = nullptr;
  QDoubleSpinBox* tolerance_ = nullptr;
  QTableWidget* models_ = nullptr;
  QLabel* live_image_ = nullptr;
  QLabel* live_status_ = nullptr;
  QTabWidget* tabs_ = nullptr;
  QPushButton* delete_ = nullptr;
  QPushButton* save_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* status_ = nullptr;
  QListWidget* samples_ = nullptr;
  QLabel* coverage_ = nullptr;
  QTableWidget* results_ = nullptr;
  CalibrationResidualsView* residuals_ = nullptr;
  QPlainTextEdit* log_ = nullptr;
};

}  // namespace telesphere::console
