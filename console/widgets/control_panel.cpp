// SPDX-License-Identifier: MIT
/// @brief ControlPanel: editors, apply buttons, the robot's values, the reply log.
#include "console/widgets/control_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QDateTime>
#include <QPushButton>
#include <QSpinBox>
#include <cmath>
#include <functional>
#include <limits>

#include "console/widgets/console_session.h"
#include "console/widgets/link_labels.h"
#include "robot/link/sphere_radius.h"

namespace telesphere::console {

ControlPanel::ControlPanel(ConsoleSession& session, QWidget* parent) : QWidget(parent), session_(session) {
  auto* grid = new QGridLayout(this);
  grid->setContentsMargins(4, 4, 4, 4);
  grid->addWidget(new QLabel("<i>set</i>"), 0, 1);
  grid->addWidget(new QLabel("<i>robot now</i>"), 0, 3);
  int row = 1;
  const auto addRow = [&](const QString& name, QWidget* editor, QWidget* extra, QLabel*& now,
                          const std::function<void()>& apply) {
    grid->addWidget(new QLabel(name), row, 0);
    if (extra) {
      auto* box = new QWidget;
      auto* h = new QHBoxLayout(box);
      h->setContentsMargins(0, 0, 0, 0);
      h->addWidget(editor);
      h->addWidget(extra);
      grid->addWidget(box, row, 1);
    } else {
      grid->addWidget(editor, row, 1);
    }
    auto* button = new QPushButton("Apply");
    connect(button, &QPushButton::clicked, this, apply);
    apply_[name] = button;
    grid->addWidget(button, row, 2);
    now = new QLabel("–");
    grid->addWidget(now, row, 3);
    ++row;
  };

  mode_ = new QComboBox;
  for (auto m : {link::proto::VISUAL_MODE_FULL6D, link::proto::VISUAL_MODE_ORIENTATION3D, link::proto::VISUAL_MODE_FIXED})
    mode_->addItem(visualModeLabel(m), int(m));
  addRow("visual mode", mode_, nullptr, mode_now_, [this] {
    link::proto::ControlRequest r;
    r.set_set_visual_mode(static_cast<link::proto::VisualMode>(mode_->currentData().toInt()));
    send("set_visual_mode " + mode_->currentText(), r);
  });

  radius_ = new QDoubleSpinBox;
  radius_->setRange(link::kMinSphereRadius, link::kMaxSphereRadius);
  radius_->setDecimals(2);
  radius_->setSingleStep(0.1);
  radius_->setValue(1.0);
  radius_->setSuffix(" m");
  radius_->setToolTip("Radius r of the projection sphere: choose it near the typical closest object distance");
  addRow("sphere radius", radius_, nullptr, radius_now_, [this] {
    link::proto::ControlRequest r;
    r.set_set_sphere_radius(radius_->value());
    send(QString("set_sphere_radius %1 m").arg(radius_->value()), r);
  });

  proxy_ = new QComboBox;
  for (auto p : {link::proto::DEPTH_PROXY_FIXED, link::proto::DEPTH_PROXY_RADIUS, link::proto::DEPTH_PROXY_GRID})
    proxy_->addItem(depthProxyLabel(p, ""), int(p));
  proxy_->setToolTip("What the operator's view projects the images onto: the fixed sphere of the radius above (the "
                     "paper's method, no depth needed), one radius that follows the scene's depth at the view's "
                     "centre, or a coarse depth grid (near objects stay put; the XR app measures the depth from the "
                     "stereo pair on one core)");
  addRow("scene proxy", proxy_, nullptr, proxy_now_, [this] {
    link::proto::ControlRequest r;
    r.set_set_depth_proxy(static_cast<link::proto::DepthProxyProto>(proxy_->currentData().toInt()));
    send("set_depth_proxy " + proxy_->currentText(), r);
  });

  quality_ = new QSpinBox;
  quality_->setRange(1, 100);
  quality_->setValue(90);
  quality_->setToolTip("JPEG quality of the stereo stream: bandwidth and decode time against fidelity");
  addRow("JPEG quality", quality_, nullptr, quality_now_, [this] {
    link::proto::ControlRequest r;
    r.set_set_jpeg_quality(quality_->value());
    send(QString("set_jpeg_quality %1").arg(quality_->value()), r);
  });

  codec_ = new QComboBox;
  codec_->addItem("MJPEG", int(link::proto::VIDEO_CODEC_MJPEG));
  codec_->addItem("H.264", int(link::proto::VIDEO_CODEC_H264));
  codec_->addItem("HEVC", int(link::proto::VIDEO_CODEC_HEVC));
  codec_->setToolTip("Video codec of the stereo stream: MJPEG (every image alone; the UDP media path) or H.264/HEVC "
                     "(a fraction of the bytes, a key frame after a loss; a robot without the media path)");
  addRow("video codec", codec_, nullptr, codec_now_, [this] {
    link::proto::ControlRequest r;
    r.set_set_video_codec(static_cast<link::proto::VideoCodecProto>(codec_->currentData().toInt()));
    send("set_video_codec " + codec_->currentText(), r);
  });

  cutoff_ = new QDoubleSpinBox;
  cutoff_->setRange(0.1, 1000.0);
  cutoff_->setDecimals(1);
  cutoff_->setValue(100.0);
  cutoff_->setSuffix(" Hz");
  cutoff_off_ = new QCheckBox("off");
  cutoff_->setToolTip("Low-pass cut-off of the head target (paper: 100 Hz): smoother against later");
  addRow("filter cut-off", cutoff_, cutoff_off_, cutoff_now_, [this] {
    link::proto::ControlRequest r;
    const double f = cutoff_off_->isChecked() ? std::numeric_limits<double>::infinity() : cutoff_->value();
    r.set_set_filter_cutoff_hz(f);
    send(cutoff_off_->isChecked() ? QString("set_filter_cutoff off") : QString("set_filter_cutoff %1 Hz").arg(f), r);
  });

  jump_cm_ = new QDoubleSpinBox;
  jump_cm_->setRange(0.1, 200.0);
  jump_cm_->setDecimals(1);
  jump_cm_->setValue(10.0);
  jump_cm_->setSuffix(" cm");
  jump_deg_ = new QDoubleSpinBox;
  jump_deg_->setRange(0.1, 180.0);
  jump_deg_->setDecimals(1);
  jump_deg_->setValue(20.0);
  jump_deg_->setSuffix(" °");
  jump_cm_->setToolTip("A head target change beyond this switches to a slow approach");
  addRow("jump threshold", jump_cm_, jump_deg_, jump_now_, [this] {
    link::proto::ControlRequest r;
    r.mutable_set_jump_threshold()->set_position_m(jump_cm_->value() / 100.0);
    r.mutable_set_jump_threshold()->set_angle_deg(jump_deg_->value());
    send(QString("set_jump_threshold %1 cm / %2°").arg(jump_cm_->value()).arg(jump_deg_->value()), r);
  });

  stop_ = new QPushButton("STOP ARM");
  stop_->setStyleSheet("QPushButton { background: #b3261e; color: white; font-weight: bold; padding: 6px; }"
                       "QPushButton:disabled { background: #d9b1ad; color: #f4e9e8; }");
  stop_->setToolTip("Protective stop: the arm brakes and holds; head targets are refused until the fault is cleared");
  connect(stop_, &QPushButton::clicked, this, [this] {
    link::proto::ControlRequest r;
    r.set_arm_stop(true);
    send("arm_stop", r);
  });
  clear_ = new QPushButton("Clear fault");
  clear_->setToolTip("Re-enable the arm after a stop or fault");
  connect(clear_, &QPushButton::clicked, this, [this] {
    link::proto::ControlRequest r;
    r.set_clear_fault(true);
    send("clear_fault", r);
  });
  grid->addWidget(stop_, row, 0, 1, 2);
  grid->addWidget(clear_, row, 2, 1, 2);
  ++row;
  // Recording the session (everything on the link, MCAP) into the robot's --record-dir.
  record_ = new QPushButton("Record session");
  record_->setToolTip("Record everything on the link (frames, state, telemetry, control) to an MCAP file in the "
                      "robot's record folder; open it in Foxglove, replay it with telesphere-robot --replay");
  connect(record_, &QPushButton::clicked, this, [this] {
    const auto& health = session_.health();
    link::proto::ControlRequest r;
    const bool stop = health && health->recording().active();
    r.mutable_recording()->set_start(!stop);
    const QString name = "session-" + QDateTime::currentDateTime().toString("yyyyMMdd-HHmmss");
    if (!stop) r.mutable_recording()->set_name(name.toStdString());
    send(stop ? QString("recording: stop") : "recording: start " + name, r);
  });
  record_now_ = new QLabel("-");
  record_now_->setWordWrap(true);
  grid->addWidget(new QLabel("recording"), row, 0);
  grid->addWidget(record_now_, row, 1, 1, 2);
  grid->addWidget(record_, row, 3);
  ++row;
  // A calibration hold on the head: who holds it, and the supervisor's way to end it.
  release_head_ = new QPushButton("Release head");
  release_head_->setToolTip("End the calibration hold: the head follows the operator again");
  connect(release_head_, &QPushButton::clicked, this, [this] {
    link::proto::ControlRequest r;
    r.mutable_calibration_head_pose()->set_release(true);
    r.mutable_calibration_head_pose()->set_holder("the console (supervisor)");
    send("release head", r);
  });
  hold_now_ = new QLabel("-");
  hold_now_->setWordWrap(true);
  grid->addWidget(new QLabel("head hold"), row, 0);
  grid->addWidget(hold_now_, row, 1, 1, 2);
  grid->addWidget(release_head_, row, 3);
  ++row;
  grid->addWidget(new QLabel("replies (newest first)"), row++, 0, 1, 4);
  log_ = new QListWidget;
  log_->setMaximumHeight(110);
  grid->addWidget(log_, row++, 0, 1, 4);
  grid->setRowStretch(row, 1);

  connect(&session_, &ConsoleSession::updated, this, &ControlPanel::refresh);
  refresh();
}

QPushButton* ControlPanel::applyButton(const QString& row) const {
  const auto it = apply_.find(row);
  return it == apply_.end() ? nullptr : it->second;
}

QString ControlPanel::recordingText() const { return record_now_->text(); }

QString ControlPanel::holdText() const { return hold_now_->text(); }

QString ControlPanel::proxyText() const { return proxy_now_->text(); }

QString ControlPanel::lastOutcome() const { return log_->count() > 0 ? log_->item(0)->text() : QString(); }

void ControlPanel::send(const QString& what, link::proto::ControlRequest request) {
  session_.request(std::move(request), what, [this](const ControlOutcome& outcome) {
    auto* item = new QListWidgetItem(outcome.text());
    item->setForeground(outcome.ok ? QColor(27, 94, 32) : QColor(179, 38, 30));
    log_->insertItem(0, item);
    while (log_->count() > 50) delete log_->takeItem(log_->count() - 1);
  });
}

void ControlPanel::refresh() {
  const bool connected = session_.robot().state() == supervision::PeerState::kConnected;
  for (auto& [name, button] : apply_) button->setEnabled(connected);
  stop_->setEnabled(connected);
  clear_->setEnabled(connected);
  const auto& health = session_.health();
  record_->setEnabled(connected && health && health->recording().available());
  const auto& state = session_.robotState();
  const bool held = state && state->hold().lease() != 0;
  release_head_->setEnabled(connected && held);
  if (held) {
    const auto& h = state->hold();
    QString text = QString("held by %1 for %2 s").arg(QString::fromStdString(h.holder()))
                       .arg(double(state->t_ns() - h.since_ns()) * 1e-9, 0, 'f', 0);
    if (h.pattern_amplitude_deg() > 0) text += QString(" (pattern ±%1°)").arg(h.pattern_amplitude_deg());
    hold_now_->setText(text);
  } else if (state) {
    hold_now_->setText(state->hold().last_release().empty()
                           ? QString("not held")
                           : "not held (last: " + QString::fromStdString(state->hold().last_release()) + ")");
  }
  if (!health) return;
  const auto& rec = health->recording();
  record_->setText(rec.active() ? "Stop recording" : "Record session");
  const QString file = QString::fromStdString(rec.file()).section('/', -1);
  if (!rec.available())
    record_now_->setText("off (start the robot with --record-dir DIR)");
  else if (rec.active())
    record_now_->setText(QString("● %1: %2 MB%3").arg(file).arg(double(rec.bytes()) * 1e-6, 0, 'f', 1)
                             .arg(rec.dropped() > 0 ? QString(", %1 dropped").arg(rec.dropped()) : QString()));
  else if (!rec.file().empty())
    record_now_->setText(QString("last: %1, %2 MB%3").arg(file).arg(double(rec.bytes()) * 1e-6, 0, 'f', 1)
                             .arg(rec.dropped() > 0 || !rec.error().empty() ? " (not whole)" : ""));
  else
    record_now_->setText("not recording");
  const auto& st = health->settings();
  mode_now_->setText(visualModeLabel(st.visual_mode()));
  radius_now_->setText(QString("%1 m").arg(st.sphere_radius()));
  {
    // The robot holds the session's choice; the XR app's telemetry says what the eyes have.
    QString text = depthProxyLabel(st.depth_proxy(), "none chosen");
    if (const auto xr = session_.telemetry().xrDepthProxy())
      text += " · XR app: " + depthProxyLabel(*xr, "?");
    proxy_now_->setText(text);
  }
  quality_now_->setText(QString::number(st.jpeg_quality()));
  codec_now_->setText(videoCodecLabel(st));
  cutoff_now_->setText(std::isinf(st.filter_cutoff_hz()) ? QString("off")
                                                         : QString("%1 Hz").arg(st.filter_cutoff_hz()));
  jump_now_->setText(QString("%1 cm / %2°").arg(st.jump_position_m() * 100.0).arg(st.jump_angle_deg()));
  clear_->setToolTip(health->arm_ok() ? "Re-enable the arm after a stop or fault (the arm is ok now)"
                                      : "Re-enable the arm: " + QString::fromStdString(health->fault()));
}

}  // namespace telesphere::console
