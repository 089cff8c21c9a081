// SPDX-License-Identifier: MIT
/// @brief The console's "Calibration in use" panel (issue #15, DESIGN.md §6): which calibration
///        the robot uses now (generation, what it is, when applied) and which one the XR app
///        renders with; the wizards' latest result as a candidate with what it would change
///        (each transform in mm and °, how far each camera's image moves in px); Apply (only the
///        part the wizard measured replaces the calibration in use, console/calibration/
///        calibration_change.h) and Revert (back to the one before). Every outcome is the robot's
///        reply, logged; nothing is assumed to have worked.
#pragma once

#include <QString>
#include <QWidget>
#include <optional>

#include "calib/system_calibration.h"
#include "console/calibration/calibration_change.h"
#include "robot/link/telesphere_link.pb.h"

class QLabel;
class QPlainTextEdit;
class QPushButton;
class QTableWidget;

namespace telesphere::console {

class ConsoleSession;
struct ControlOutcome;

class CalibrationInUsePanel : public QWidget {
  Q_OBJECT

 public:
  explicit CalibrationInUsePanel(ConsoleSession& session, QWidget* parent = nullptr);

  /// A wizard's result that met its done rule: `parts` of it can be applied.
  void setCandidate(const calib::SystemCalibration& result, calibration::MeasuredParts parts, const QString& source);
  /// The buttons' actions (tests call them as a click would).
  void apply();
  void revert();
  /// Follows the robot's state (fetches a calibration it has not seen) and the XR app's telemetry
  /// (the console window calls it with its other panels, every 250 ms).
  void refresh();

  /// The robot's calibration in use as last fetched (none before the first answer).
  const std::optional<link::proto::CalibrationInUse>& inUse() const { return in_use_; }
  /// The generation the XR app renders with, from its telemetry (none: no XR app heard yet).
  std::optional<std::uint64_t> xrGeneration() const;
  /// What Apply would send (the calibration in use with the candidate's part), if both are there
  /// (Apply is enabled only when that differs from the calibration in use).
  std::optional<calib::SystemCalibration> nextCalibration() const;

 signals:
  /// After each apply or revert reply (ok or refused).
  void answered(bool ok, const QString& text);

 private:
  void fetch();
  void takeInUse(const link::proto::CalibrationInUse& in_use);
  void takeReply(const ControlOutcome& outcome);  ///< of an apply or revert
  void showChanges();
  void log(const QString& text, bool ok);

  ConsoleSession& session_;
  std::optional<link::proto::CalibrationInUse> in_use_;
  std::optional<calib::SystemCalibration> in_use_parsed_;
  bool fetching_ = false;
  bool candidate_changes_ = false;  ///< Apply would change something
  struct Candidate {
    calib::SystemCalibration result;
    calibration::MeasuredParts parts;
    QString source;
  };
  std::optional<Candidate> candidate_;
  QLabel* robot_ = nullptr;
  QLabel* xr_ = nullptr;
  QLabel* candidate_label_ = nullptr;
  QTableWidget* changes_ = nullptr;
  QPushButton* apply_ = nullptr;
  QPushButton* revert_ = nullptr;
  QPlainTextEdit* log_ = nullptr;
};

}  // namespace telesphere::console
