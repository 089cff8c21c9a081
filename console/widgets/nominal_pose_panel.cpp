// SPDX-License-Identifier: MIT
/// @brief NominalPosePanel: three steps, gated capture, confirm or undo.
#include "console/widgets/nominal_pose_panel.h"

#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "console/widgets/console_session.h"
#include "console/widgets/link_labels.h"
#include "robot/link/link_pose.h"

namespace telesphere::console {
namespace {

/// "+12.3°", "−0.4°", "0.0°" (no negative zero).
QString degrees(double value_deg) {
  const double rounded = std::round(value_deg * 10.0) / 10.0;
  if (rounded == 0.0) return "0.0°";
  return QString("%1%2°").arg(rounded > 0 ? "+" : "−").arg(std::abs(rounded), 0, 'f', 1);
}

}  // namespace

NominalPosePanel::NominalPosePanel(ConsoleSession& session, QWidget* parent) : QWidget(parent), session_(session) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(4, 4, 4, 4);
  layout->addWidget(new QLabel("<b>1.</b> Move the robot head to its nominal pose and hold it there."));
  hold_ = new QPushButton("Move head to nominal pose");
  layout->addWidget(hold_);
  layout->addWidget(new QLabel("<b>2.</b> Ask the operator to look straight ahead and keep still."));
  head_ = new QLabel;
  gate_label_ = new QLabel;
  gate_label_->setWordWrap(true);
  layout->addWidget(head_);
  layout->addWidget(gate_label_);
  capture_ = new QPushButton("Capture");
  capture_->setToolTip("Enabled only while fresh head poses arrive and the head is still");
  layout->addWidget(capture_);
  layout->addWidget(new QLabel("<b>3.</b> Check the mapping, then confirm or undo."));
  captured_ = new QLabel("nothing captured yet");
  captured_->setWordWrap(true);
  layout->addWidget(captured_);
  auto* row = new QHBoxLayout;
  confirm_ = new QPushButton("Confirm");
  undo_ = new QPushButton("Undo");
  undo_->setToolTip("Back to the previous nominal pose (drops a capture not confirmed yet)");
  row->addWidget(confirm_);
  row->addWidget(undo_);
  layout->addLayout(row);
  status_ = new QLabel;
  status_->setWordWrap(true);
  layout->addWidget(status_);
  layout->addStretch(1);

  connect(hold_, &QPushButton::clicked, this,
          [this] { step(link::proto::NOMINAL_REQUEST_HOLD, "nominal: move head to the nominal pose"); });
  connect(capture_, &QPushButton::clicked, this, [this] { step(link::proto::NOMINAL_REQUEST_CAPTURE, "nominal: capture"); });
  connect(confirm_, &QPushButton::clicked, this, [this] { step(link::proto::NOMINAL_REQUEST_CONFIRM, "nominal: confirm"); });
  connect(undo_, &QPushButton::clicked, this, [this] { step(link::proto::NOMINAL_REQUEST_UNDO, "nominal: undo"); });
  connect(&session_, &ConsoleSession::updated, this, &NominalPosePanel::refresh);
  refresh();
}

void NominalPosePanel::step(link::proto::NominalStepRequest request, const QString& what) {
  link::proto::ControlRequest r;
  r.set_nominal_step(request);
  busy_ = true;
  status_->setText(what + " …");
  session_.request(r, what, [this](const ControlOutcome& outcome) {
    busy_ = false;
    if (outcome.ok && outcome.reply.has_nominal()) mapping_ = outcome.reply.nominal();
    status_->setText(outcome.text());
    refresh();
  });
  refresh();
}

void NominalPosePanel::refresh() {
  gate_ = supervision::evaluateNominalGate(session_.telemetry().recentHeadPoses(), session_.now());
  if (gate_.angles)
    head_->setText(QString("operator head: yaw %1, pitch %2, roll %3")
                       .arg(degrees(gate_.angles->yaw * 180.0 / M_PI), degrees(gate_.angles->pitch * 180.0 / M_PI),
                            degrees(gate_.angles->roll * 180.0 / M_PI)));
  else
    head_->setText("operator head: no pose yet");
  gate_label_->setText(gate_.can_capture
                           ? QString("<span style='color:#1b5e20'>✓ fresh (newest %1 s old) and still (%2° / %3 cm "
                                     "in 0.5 s)</span>")
                                 .arg(std::max(0.0, gate_.age_s), 0, 'f', 2)
                                 .arg(gate_.turn_deg, 0, 'f', 2)
                                 .arg(gate_.move_m * 100.0, 0, 'f', 2)
                           : "<span style='color:#b3261e'>✗ " + QString::fromStdString(gate_.reason).toHtmlEscaped() + "</span>");

  const auto& state = session_.robotState();
  const bool connected = session_.robot().state() == supervision::PeerState::kConnected;
  const link::proto::NominalStep step = state ? state->nominal_step() : link::proto::NOMINAL_STEP_FOLLOWING;
  hold_->setEnabled(connected && !busy_);
  capture_->setEnabled(connected && !busy_ && step != link::proto::NOMINAL_STEP_FOLLOWING && gate_.can_capture);
  confirm_->setEnabled(connected && !busy_ && step == link::proto::NOMINAL_STEP_CAPTURED);
  undo_->setEnabled(connected && !busy_ &&
                    (step != link::proto::NOMINAL_STEP_FOLLOWING || (mapping_ && mapping_->has_previous())));

  if (mapping_ && mapping_->step() == link::proto::NOMINAL_STEP_CAPTURED) {
    const Eigen::Isometry3d T = link::fromLinkPose(mapping_->t_robot_vr());
    captured_->setText(QString("captured: yaw %1 kept; pitch %2 and roll %3 removed.<br>T_robot_vr: "
                               "t = (%4, %5, %6) m")
                           .arg(degrees(mapping_->yaw_deg()), degrees(mapping_->pitch_deg()), degrees(mapping_->roll_deg()))
                           .arg(T.translation().x(), 0, 'f', 3)
                           .arg(T.translation().y(), 0, 'f', 3)
                           .arg(T.translation().z(), 0, 'f', 3));
  } else if (mapping_) {
    captured_->setText("robot: " + nominalStepLabel(mapping_->step()) +
                       (mapping_->has_previous() ? " (an earlier nominal pose can be restored)" : ""));
  }
  if (!busy_ && state && status_->text().isEmpty()) status_->setText("robot: " + nominalStepLabel(step));
}

QString NominalPosePanel::statusText() const { return status_->text(); }

}  // namespace telesphere::console
