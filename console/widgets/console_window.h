// SPDX-License-Identifier: MIT
/// @brief The supervisor's main window (DESIGN.md §1): the fault banner and the connection line
///        on top, the live graphs in the middle (one tab per figure, and the Internet link panel's
///        four on a tab of their own; only the visible ones are
///        redrawn, by one coalesced timer at ≤ 30 Hz), and docked panels around them: health,
///        camera preview, control, nominal pose, study (StudyPanel). Layout and choices persist in
///        QSettings. The calibration wizards of a later issue dock in beside these.
#pragma once

#include <QMainWindow>
#include <QTimer>
#include <vector>

class QDockWidget;
class QLabel;
class QTabWidget;

namespace telesphere::console {

class CameraPreviewPanel;
class ConsoleSession;
class ControlPanel;
class FaultBanner;
class HealthPanel;
class LinkPanel;
class LivePlot;
class NominalPosePanel;
class StudyPanel;
class CalibrationPanel;
class HandEyePanel;
class CalibrationInUsePanel;

class ConsoleWindow : public QMainWindow {
  Q_OBJECT

 public:
  /// Redraws at most this often (coalesced over all data arrivals).
  static constexpr int kRedrawIntervalMs = 33;

  explicit ConsoleWindow(ConsoleSession& session, QWidget* parent = nullptr);
  ~ConsoleWindow() override;

  ConsoleSession& session() { return session_; }
  const std::vector<LivePlot*>& plots() const { return plots_; }
  QTabWidget* plotTabs() const { return tabs_; }
  HealthPanel* healthPanel() const { return health_; }
  LinkPanel* linkPanel() const { return link_; }
  CameraPreviewPanel* previewPanel() const { return preview_; }
  ControlPanel* controlPanel() const { return control_; }
  NominalPosePanel* nominalPanel() const { return nominal_; }
  StudyPanel* studyPanel() const { return study_; }
  CalibrationPanel* calibrationPanel() const { return calibration_; }
  HandEyePanel* handEyePanel() const { return hand_eye_; }
  CalibrationInUsePanel* calibrationInUsePanel() const { return in_use_; }
  FaultBanner* faultBanner() const { return banner_; }
  /// The dock holding `panel` (to show it, or to grab it for a screenshot).
  QDockWidget* dockOf(QWidget* panel) const;
  /// The line under the banner ("robot: connected for …", "waiting for robot at …").
  QString connectionText() const;

  /// Redraws the visible plot now if anything changed (what the redraw timer does).
  void redraw(bool force = false);

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  void refreshPanels();
  /// The plots on the tab shown (one, or the link panel's four).
  std::vector<LivePlot*> visiblePlots() const;
  void updateDataHold();

  ConsoleSession& session_;
  FaultBanner* banner_;
  QLabel* connection_;
  QTabWidget* tabs_;
  std::vector<LivePlot*> plots_;
  HealthPanel* health_;
  LinkPanel* link_;
  CameraPreviewPanel* preview_;
  ControlPanel* control_;
  NominalPosePanel* nominal_;
  StudyPanel* study_;
  CalibrationPanel* calibration_;
  HandEyePanel* hand_eye_;
  CalibrationInUsePanel* in_use_;
  std::vector<QDockWidget*> docks_;
  QTimer redraw_timer_, panel_timer_;
  std::uint64_t drawn_version_ = ~0ull;
  qint64 drawn_at_ms_ = 0;
};

}  // namespace telesphere::console
