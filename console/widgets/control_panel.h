// SPDX-License-Identifier: MIT
/// @brief The knobs the supervisor turns live (DESIGN.md §7: every change is a control request
///        with an explicit reply, shown; nothing is assumed to have worked): visual mode, sphere
///        radius, scene proxy (#35: the robot holds the session's choice; the row also says what
///        the XR app renders with), JPEG quality, video codec, filter cut-off, jump threshold, arm stop and clear fault, who holds
///        the head for calibration and "release head". Each row shows what the robot has in force
///        now next to the editor.
#pragma once

#include <QWidget>
#include <map>

#include "robot/link/telesphere_link.pb.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QListWidget;
class QPushButton;
class QSpinBox;

namespace telesphere::console {

class ConsoleSession;

class ControlPanel : public QWidget {
  Q_OBJECT

 public:
  explicit ControlPanel(ConsoleSession& session, QWidget* parent = nullptr);
  void refresh();

  // The editors and buttons, for tests that drive the panel like a user.
  QComboBox* modeBox() const { return mode_; }
  QDoubleSpinBox* radiusBox() const { return radius_; }
  QComboBox* proxyBox() const { return proxy_; }
  QString proxyText() const;  ///< the "robot now" column of the scene proxy row
  QSpinBox* qualityBox() const { return quality_; }
  QComboBox* codecBox() const { return codec_; }
  QDoubleSpinBox* cutoffBox() const { return cutoff_; }
  QCheckBox* cutoffOffBox() const { return cutoff_off_; }
  QDoubleSpinBox* jumpPositionBox() const { return jump_cm_; }
  QDoubleSpinBox* jumpAngleBox() const { return jump_deg_; }
  QPushButton* applyButton(const QString& row) const;
  QPushButton* stopButton() const { return stop_; }
  QPushButton* clearFaultButton() const { return clear_; }
  /// Starts a recording (session-DATE-TIME) in the robot's record folder, or stops the one running.
  QPushButton* recordButton() const { return record_; }
  QString recordingText() const;
  /// Ends any calibration hold on the head (a wizard that went away, or one to stop).
  QPushButton* releaseHeadButton() const { return release_head_; }
  /// "held by hand-eye wizard (headless), pid 4242 on rig-pc for 12 s (pattern ±20°)", or "not held".
  QString holdText() const;
  /// The newest reply, in words ("set_sphere_radius 2: ok").
  QString lastOutcome() const;

 private:
  void send(const QString& what, link::proto::ControlRequest request);

  ConsoleSession& session_;
  QComboBox* mode_;
  QDoubleSpinBox* radius_;
  QComboBox* proxy_;
  QSpinBox* quality_;
  QComboBox* codec_;
  QDoubleSpinBox* cutoff_;
  QCheckBox* cutoff_off_;
  QDoubleSpinBox* jump_cm_;
  QDoubleSpinBox* jump_deg_;
  QLabel *mode_now_, *radius_now_, *proxy_now_, *quality_now_, *codec_now_, *cutoff_now_, *jump_now_;
  QPushButton* stop_;
  QPushButton* clear_;
  QPushButton* record_;
  QLabel* record_now_;
  QPushButton* release_head_;
  QLabel* hold_now_;
  QListWidget* log_;
  std::map<QString, QPushButton*> apply_;
};

}  // namespace telesphere::console
