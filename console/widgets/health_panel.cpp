// SPDX-License-Identifier: MIT
/// @brief HealthPanel: a two-column tree, updated in place.
#include "console/widgets/health_panel.h"

#include "robot/link/proto_enums.h"

#include <QHeaderView>
#include <QTreeWidget>
#include <QVBoxLayout>
#include <cmath>

#include "console/widgets/console_session.h"
#include "console/widgets/link_labels.h"
#include "robot/link/link_trust_text.h"

namespace telesphere::console {
namespace {

QString number(double v, int decimals = 1) { return QString::number(v, 'f', decimals); }

}  // namespace

HealthPanel::HealthPanel(ConsoleSession& session, QWidget* parent) : QWidget(parent), session_(session) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  tree_ = new QTreeWidget;
  tree_->setColumnCount(2);
  tree_->setHeaderLabels({"", "value"});
  tree_->header()->setSectionResizeMode(0, QHeaderView::ResizeToContents);
  tree_->header()->setSectionResizeMode(1, QHeaderView::Stretch);
  tree_->header()->setStretchLastSection(true);
  tree_->setRootIsDecorated(true);
  tree_->setWordWrap(true);
  tree_->setTextElideMode(Qt::ElideNone);
  tree_->setUniformRowHeights(false);
  tree_->setMinimumWidth(500);
  layout->addWidget(tree_);
  for (const char* name : {"Robot", "Trust", "Cameras", "Arm and head", "XR app", "Link and telemetry"}) {
    auto* item = new QTreeWidgetItem(tree_, {name});
    QFont bold = item->font(0);
    bold.setBold(true);
    item->setFont(0, bold);
    item->setExpanded(true);
    sections_[name] = item;
  }
  refresh();
}

void HealthPanel::setRow(const QString& section, const QString& key, const QString& value, bool warn) {
  QTreeWidgetItem* parent = sections_.at(section);
  QTreeWidgetItem* row = nullptr;
  for (int i = 0; i < parent->childCount(); ++i)
    if (parent->child(i)->text(0) == key) row = parent->child(i);
  if (!row) row = new QTreeWidgetItem(parent, {key});
  if (row->text(1) != value) {
    row->setText(1, value);
    row->setToolTip(1, value);
  }
  const QBrush brush = warn ? QBrush(QColor(179, 38, 30)) : QBrush();
  row->setForeground(1, brush);
  row->setForeground(0, brush);
}

QString HealthPanel::value(const QString& section, const QString& key) const {
  const auto it = sections_.find(section);
  if (it == sections_.end()) return {};
  for (int i = 0; i < it->second->childCount(); ++i)
    if (it->second->child(i)->text(0) == key) return it->second->child(i)->text(1);
  return {};
}

void HealthPanel::refresh() {
  const ConsoleSession& s = session_;
  const supervision::PeerMonitor& robot = s.robot();
  QString robot_text = QString::fromStdString(robot.describe());
  if (robot.state() == supervision::PeerState::kWaiting)
    robot_text = "waiting for robot at " + s.endpoint() + " for " + QString::fromStdString(supervision::formatDuration(robot.seconds())) +
                 " (retrying)";
  if (robot.reconnects() > 0) robot_text += QString(" (%1 reconnects)").arg(robot.reconnects());
  setRow("Robot", "link", robot_text, robot.state() != supervision::PeerState::kConnected);
  setRow("Robot", "endpoint", s.endpoint());
  if (const auto clock = s.clock())
    setRow("Robot", "clock offset", QString("%1 ms ± %2 ms (round trip %3 ms)")
                                        .arg(number(double(clock->server_to_client_offset_ns) * 1e-6, 3))
                                        .arg(number(double(clock->uncertainty_ns) * 1e-6, 3))
                                        .arg(number(double(clock->round_trip_ns) * 1e-6, 3)));
  else
    setRow("Robot", "clock offset", "not measured yet (no ping answered)", true);
  setRow("Robot", "restarts seen", QString::number(s.activity().robot_restarts));

  // Trust (DESIGN.md §10): this console's key, the robot's keys, every refusal.
  const auto& credentials = s.options().endpoints.credentials;
  setRow("Trust", "this console",
         credentials.secure()
             ? QString::fromStdString(credentials.own->key.name + " (" +
                                      std::string(link::trust::linkRoleName(credentials.own->key.role)) + " key)")
             : QString("INSECURE LINK (--insecure): no key, nothing encrypted"),
         !credentials.secure());
  if (!s.activity().refused_reason.empty())
    setRow("Trust", "refused by the robot",
           QString("%1 (%2 handshakes)")
               .arg(QString::fromStdString(s.activity().refused_reason))
               .arg(s.activity().handshakes_refused),
           true);
  else
    setRow("Trust", "refused by the robot", "no");

  const auto& health = s.health();
  if (health) {
    // Everything below is the newest report; while the robot is silent or gone it is the last known.
    const double report_age = robot.state() == supervision::PeerState::kConnected ? 0.0 : robot.seconds();
    setRow("Robot", "report", report_age > 0 ? QString("last known, %1 old").arg(QString::fromStdString(supervision::formatDuration(report_age)))
                                             : QString("live"),
           report_age > 0);
    setRow("Robot", "arm / cameras", QString::fromStdString(health->arm() + " / " + health->cameras_kind()));
    setRow("Trust", "robot", QString::fromStdString(link::trustSummary(health->trust())), health->trust().insecure());
    const std::string refused = link::refusalSummary(health->trust());
    setRow("Trust", "refused peers", refused.empty() ? QString("none") : QString::fromStdString(refused), !refused.empty());
    if (health->trust().allowed_errors_size() > 0)
      setRow("Trust", "allowed/ errors", QString::fromStdString(health->trust().allowed_errors(0)), true);
    setRow("Robot", "up", QString::fromStdString(supervision::formatDuration(double(health->t_ns() - health->started_ns()) * 1e-9)));
    for (int i = 0; i < health->cameras_size(); ++i) {
      const auto& c = health->cameras(i);
      const QString name = i == 0 ? QString("left") : i == 1 ? QString("right") : QString("camera %1").arg(i);
      setRow("Cameras", name,
             QString("%1 fps · %2×%3 · exposure %4 ms · %5")
                 .arg(number(c.fps()))
                 .arg(c.width())
                 .arg(c.height())
                 .arg(number(c.exposure_us() * 1e-3))
                 .arg(QString::fromStdString(c.name())),
             c.fps() <= 0.0);
      const std::uint64_t drops = c.incomplete() + c.lost() + c.unpaired();
      setRow("Cameras", name + " drops",
             QString("%1 incomplete · %2 lost · %3 unpaired · %4 reconnects")
                 .arg(c.incomplete())
                 .arg(c.lost())
                 .arg(c.unpaired())
                 .arg(c.reconnects()),
             drops > 0 || c.reconnects() > 0);
      if (!c.last_error().empty()) setRow("Cameras", name + " error", QString::fromStdString(c.last_error()), true);
    }
    setRow("Cameras", "video path",
           QString("%1 pairs · %2 sent · %3 late · %4 failed").arg(health->pairs()).arg(health->frames_sent())
               .arg(health->pairs_dropped_queue()).arg(health->encode_failures()),
           health->encode_failures() > 0);
    setRow("Cameras", "encode", QString("%1 ms (both images, last pair)").arg(number(health->encode_ms_last())));
    const auto& st = health->settings();
    // What the frames carry (#34): MJPEG at a quality, or H.264/HEVC at a rate, and who encodes.
    setRow("Cameras", "codec", videoCodecLabel(st), !link::fromProto(st.video_codec()));
    setRow("Arm and head", "arm", health->arm_ok() ? "ok" : "FAULT: " + QString::fromStdString(health->fault()),
           !health->arm_ok());
    setRow("Arm and head", "mode / radius", QString("%1 · r = %2 m").arg(visualModeLabel(st.visual_mode())).arg(st.sphere_radius()));
    setRow("Arm and head", "JPEG / filter / jump",
           QString("q%1 · %2 · > %3 cm or %4°")
               .arg(st.jpeg_quality())
               .arg(std::isinf(st.filter_cutoff_hz()) ? QString("filter off") : number(st.filter_cutoff_hz()) + " Hz")
               .arg(number(st.jump_position_m() * 100.0))
               .arg(number(st.jump_angle_deg())));
    setRow("Arm and head", "head pose age",
           health->head_target_age_ns() < 0 ? QString("no head pose yet")
                                            : number(double(health->head_target_age_ns()) * 1e-6) + " ms",
           health->head_target_age_ns() < 0 || health->head_target_age_ns() > 500'000'000);
    QStringList rejects;
    for (const auto& r : health->head_rejects())
      if (r.count() > 0) rejects << QString("%1 %2").arg(QString::fromStdString(r.name())).arg(r.count());
    setRow("Arm and head", "targets",
           QString("%1 sent · %2 jumps · %3 unreachable").arg(health->targets_sent()).arg(health->jumps()).arg(health->unreachable()));
    setRow("Arm and head", "rejected", rejects.isEmpty() ? QString("none") : rejects.join(" · "), !rejects.isEmpty());
    if (health->has_xarm()) {
      const auto& x = health->xarm();
      setRow("Arm and head", "xArm controller",
             QString("%1 · SN %2 · protocol id %3")
                 .arg(QString::fromStdString(x.firmware()), x.serial().empty() ? QString("?") : QString::fromStdString(x.serial()))
                 .arg(x.protocol()));
      setRow("Arm and head", "xArm link",
             QString("delay %1 ms · report jitter p99 %2 ms · %3 ppm · %4 reconnects")
                 .arg(number(x.link_delay_ms(), 2), number(x.report_jitter_ms_p99(), 2), number(x.report_drift_ppm()))
                 .arg(x.reconnects()),
             x.report_jitter_ms_p99() > 5.0);
      setRow("Arm and head", "xArm refused",
             QString("%1 jumps · %2 beyond limits (of %3 targets)").arg(x.refused_jumps()).arg(x.refused_limits()).arg(x.targets_sent()),
             x.refused_jumps() + x.refused_limits() > 0);
      setRow("Arm and head", "xArm payload",
             x.payload_read() ? QString("%1 kg at (%2, %3, %4) mm · collision sensitivity %5")
                                    .arg(number(x.payload_kg(), 3), number(x.payload_com_x_mm()), number(x.payload_com_y_mm()),
                                         number(x.payload_com_z_mm()))
                                    .arg(x.collision_sensitivity())
                              : "not read back: " + QString::fromStdString(x.readback_error()),
             !x.payload_read());
    }
  }
  if (const auto& state = s.robotState())
    setRow("Arm and head", "nominal pose",
           state->nominal_set() ? nominalStepLabel(state->nominal_step()) : nominalStepLabel(state->nominal_step()) + " (no mapping yet)",
           !state->nominal_set());

  const supervision::PeerMonitor& xr = s.xr();
  setRow("XR app", "link", xr.state() == supervision::PeerState::kWaiting ? QString("not heard yet (through the robot)")
                                                             : QString::fromStdString(xr.describe()),
         xr.state() != supervision::PeerState::kConnected);
  if (const auto& x = s.xrStats()) {
    setRow("XR app", "frames",
           QString("%1 fps · render %2 ms · %3 missed").arg(number(x->fps())).arg(number(x->render_ms())).arg(x->missed_frames()));
    setRow("XR app", "image age",
           QString("p50 %1 ms · p99 %2 ms (capture → display)").arg(number(x->image_age_p50_ms())).arg(number(x->image_age_p99_ms())));
  }
  if (const auto mode = s.telemetry().xrVisualMode())
    setRow("XR app", "renders", QString("%1 · r = %2 m").arg(visualModeLabel(*mode)).arg(s.telemetry().xrSphereRadius().value_or(0)));
  if (const auto unmeasured = s.telemetry().xrUnmeasuredPose()) {
    const bool now = unmeasured->shown_dimmed || unmeasured->holding_measured;
    setRow("XR app", "camera pose",
           QString("%1 · %2 display frames without a measured pose so far")
               .arg(unmeasured->shown_dimmed       ? "NOT measured: shown dimmed"
                    : unmeasured->holding_measured ? "NOT measured: holding the last measured frame"
                                                   : "measured")
               .arg(s.telemetry().counts().xr_frames_unmeasured),
           now);
  }

  const link::LinkStatsSnapshot link = s.linkStats();
  QStringList drops;
  for (int r = 0; r < int(link::DropReason::kCount); ++r)
    if (link.dropped_by_reason[r] > 0 && r != int(link::DropReason::kSuperseded))
      drops << QString("%1 %2").arg(QString::fromStdString(std::string(link::dropReasonName(link::DropReason(r))))).arg(link.dropped_by_reason[r]);
  if (health)
    for (const auto& d : health->link_drops()) drops << QString("robot: %1 %2").arg(QString::fromStdString(d.name())).arg(d.count());
  setRow("Link and telemetry", "dropped", drops.isEmpty() ? QString("nothing") : drops.join(" · "), !drops.isEmpty());
  const telemetry::TelemetryCounts& t = s.telemetry().counts();
  const std::uint64_t lost = t.robot_batches_lost + t.xr_batches_lost + s.activity().telemetry_overflow;
  if (health && health->telemetry_samples_dropped() > 0)
    setRow("Link and telemetry", "robot dropped", QString("%1 telemetry samples never sent").arg(health->telemetry_samples_dropped()), true);
  setRow("Link and telemetry", "telemetry",
         QString("%1 robot + %2 XR batches · %3 lost · %4 unsynced")
             .arg(t.robot_batches)
             .arg(t.xr_batches)
             .arg(lost)
             .arg(t.unsynced_batches),
         lost > 0);
  setRow("Link and telemetry", "in memory",
         QString("%1 samples · %2 MB · last %3 s kept")
             .arg(s.series().totalSamples())
             .arg(number(double(s.series().bytes()) / 1e6, 2))
             .arg(s.series().retention()));
}

}  // namespace telesphere::console
