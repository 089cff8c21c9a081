// SPDX-License-Identifier: MIT
/// @brief The guided nominal-pose step (DESIGN.md §2; robot side: HeadLoop's nominal step):
///        1. the robot moves the head to T_robot_nom and holds it; 2. the operator is asked to
///        look straight ahead while the panel shows their head's yaw, pitch and roll and whether
///        it is still, from fresh head poses; capture is possible only then; 3. the captured
///        mapping is shown with the pitch and roll it removed; confirm, or undo back to the
///        previous nominal pose.
#pragma once

#include <QWidget>

#include "console/supervision/nominal_pose_gate.h"
#include "robot/link/telesphere_link.pb.h"

class QLabel;
class QPushButton;

namespace telesphere::console {

class ConsoleSession;

class NominalPosePanel : public QWidget {
  Q_OBJECT

 public:
  explicit NominalPosePanel(ConsoleSession& session, QWidget* parent = nullptr);
  void refresh();

  QPushButton* holdButton() const { return hold_; }
  QPushButton* captureButton() const { return capture_; }
  QPushButton* confirmButton() const { return confirm_; }
  QPushButton* undoButton() const { return undo_; }
  const supervision::NominalGateStatus& gate() const { return gate_; }
  /// The newest mapping a reply carried (step, angles, T_robot_vr).
  const std::optional<link::proto::NominalMapping>& mapping() const { return mapping_; }
  QString statusText() const;

 private:
  void step(link::proto::NominalStepRequest request, const QString& what);

  ConsoleSession& session_;
  QPushButton *hold_, *capture_, *confirm_, *undo_;
  QLabel *head_, *gate_label_, *captured_, *status_;
  supervision::NominalGateStatus gate_;
  std::optional<link::proto::NominalMapping> mapping_;
  bool busy_ = false;  ///< a request is in flight
};

}  // namespace telesphere::console
