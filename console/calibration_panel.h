// SPDX-License-Identifier: MIT
/// @brief The console's Calibration panel (issue #15, paper §III-B): the intrinsic and stereo
///        calibration on the live robot, run in a worker thread with progress and cancel (the
///        window never waits on it), the done rule stated with its numbers, the kept samples
///        as thumbnails with their corners (delete any, then solve again), coverage per camera
///        in polar bins, every parameter with its standard deviation, the residuals against polar
///        angle and the worst views (console/calibration_residuals_view.h), and save as our file,
///        kalibr camchain or Basalt JSON (only a result that meets the done rule). The procedure is console/calibration/intrinsics_procedure.h;
///        the panel talks to the robot through its own link client.
///
/// Not here yet (issue #15 stays open): hand-eye, a live preview with corners, applying a
/// result to the running robot and XR app.
#pragma once

#include <QWidget>
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "console/calibration/intrinsics_procedure.h"
#include "robot/link/link_endpoints.h"

class QComboBox;
class QLabel;
class QListWidget;
class QPlainTextEdit;
class QProgressBar;
class QPushButton;
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
  void cancel();
  void deleteSample(int index);  ///< then solves again in the worker
  bool saveTo(const QString& path, const QString& format, QString* error);

  bool running() const { return worker_.joinable() && !finished_; }
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
  void setBusy(bool busy);

  link::LinkEndpoints endpoints_;
  calibration::IntrinsicsProcedureOptions options_;
  std::thread worker_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> finished_{true};
  std::mutex result_mutex_;
  std::optional<calibration::IntrinsicsOutcome> pending_;  ///< the worker's result, until taken
  std::optional<calibration::IntrinsicsOutcome> outcome_;

  QLabel* rule_ = nullptr;
  QComboBox* model_ = nullptr;
  QPushButton* auto_ = nullptr;
  QPushButton* cancel_button_ = nullptr;
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
