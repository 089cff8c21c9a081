// SPDX-License-Identifier: MIT
/// @brief ConsoleSession: the poll, the faults, the control requests.
#include "console/widgets/console_session.h"

#include <QMetaObject>
#include <algorithm>

namespace telesphere::console {

QString ControlOutcome::text() const {
  if (!answered) return what + ": no reply from the robot (timed out)";
  if (!ok) return what + ": refused: " + error;
  if (reply.pending()) return what + ": under way (the robot state shows the outcome)";
  return what + ": ok";
}

ConsoleSession::ConsoleSession(const ConsoleSessionOptions& options, QObject* parent)
    : QObject(parent),
      options_(options),
      origin_ns_(link::linkNowNs()),
      client_(std::make_unique<link::LinkClient>(
          options.endpoints, link::LinkClient::Options{.frames = false, .telemetry = true, .previews = true})),
      model_(series_, origin_ns_),
      robot_(origin_ns_, options.robot),
      xr_(origin_ns_, options.xr),
      control_(std::make_unique<link::ControlQueue>(*client_, options.control_timeout)) {
  series_.setRetention(options.retention_s);
  timer_.setInterval(options.poll_ms);
  connect(&timer_, &QTimer::timeout, this, &ConsoleSession::poll);
  timer_.start();
}

ConsoleSession::~ConsoleSession() {
  timer_.stop();
  control_.reset();  // joins the worker: no reply callback runs after this
}

QString ConsoleSession::endpoint() const {
  return QString::fromStdString(options_.endpoints.connect(link::LinkEndpoints::kControl));
}

double ConsoleSession::now() const { return model_.plotTime(link::linkNowNs()); }

void ConsoleSession::acknowledgeFaults() {
  faults_.acknowledgeAll();
  fault_version_seen_ = faults_.version();
  emit faultsChanged();
}

void ConsoleSession::request(link::proto::ControlRequest request, const QString& what,
                             std::function<void(const ControlOutcome&)> done) {
  const double sent = now();
  // The worker is joined in the destructor, so `this` outlives every call of this callback; the
  // event it posts is dropped by Qt if the session is gone before the event loop gets to it.
  ConsoleSession* self = this;
  control_->send(std::move(request), [self, what, sent, done = std::move(done)](
                                         const std::optional<link::proto::ControlReply>& reply) {
    ControlOutcome outcome;
    outcome.what = what;
    outcome.sent_s = sent;
    outcome.answered = reply.has_value();
    if (reply) {
      outcome.ok = reply->ok();
      outcome.error = QString::fromStdString(reply->error());
      outcome.reply = *reply;
    }
    QMetaObject::invokeMethod(
        self,
        [self, outcome, done]() mutable {
          outcome.replied_s = self->now();
          if (done) done(outcome);
          emit self->controlAnswered(outcome.text());
          if (outcome.ok) emit self->controlAccepted(outcome.replied_s, outcome.what);
        },
        Qt::QueuedConnection);
  });
}

void ConsoleSession::poll() {
  const std::int64_t now_ns = link::linkNowNs();
  const link::LinkActivity activity = client_->activity();
  if (activity.robot_restarts != activity_.robot_restarts) {
    model_.robotRestarted();
    faults_.raise("robot.restart", "the robot restarted (now process " + std::to_string(activity.robot_instance) + ")",
                  now_ns);
    faults_.clear("robot.restart", now_ns);
    camera_reconnects_.clear();
  }
  activity_ = activity;

  std::optional<std::int64_t> offset;
  if (const auto e = client_->clock().estimate()) offset = e->server_to_client_offset_ns;
  for (const auto& envelope : client_->takeTelemetry()) {
    model_.ingest(envelope, offset);
    if (tap_) tap_(envelope, offset);
  }
  const double t_now = model_.plotTime(now_ns);
  series_.trim(t_now, hold_from_.value_or(t_now));

  if (auto h = client_->latestRobotHealth()) health_ = std::move(h);
  if (auto s = client_->latestRobotState()) state_ = std::move(s);
  if (auto x = client_->latestXrStats()) xr_stats_ = std::move(x);

  robot_.update(std::max(activity_.robot_pong_ns, activity_.robot_state_ns), now_ns);
  xr_.update(activity_.xr_ns, now_ns);

  if (auto p = client_->takeLatestPreview()) {
    CameraPreview preview;
    preview.sequence = p->preview.sequence();
    preview.capture_s = offset ? model_.plotTime(p->preview.capture_ns() + *offset) : t_now;
    preview.source_width = int(p->preview.source_width());
    preview.source_height = int(p->preview.source_height());
    const bool ok_l = preview.left.loadFromData(p->left_jpeg.data(), int(p->left_jpeg.size()), "JPEG");
    const bool ok_r = preview.right.loadFromData(p->right_jpeg.data(), int(p->right_jpeg.size()), "JPEG");
    if (ok_l && ok_r) {
      preview_ = std::move(preview);
      emit previewChanged();
    }
  }
  updateFaults(now_ns);
  emit updated();
}

void ConsoleSession::updateFaults(std::int64_t now_ns) {
  const auto unmeasured = model_.xrUnmeasuredPose();
  if (unmeasured && (unmeasured->shown_dimmed || unmeasured->holding_measured)) {
    faults_.raise("xr.pose_unmeasured",
                  std::string("camera frames without a measured camera pose (no joint state at their capture time): "
                              "the XR app ") +
                      (unmeasured->shown_dimmed ? "shows them dimmed" : "holds the last measured frame"),
                  now_ns);
  } else {
    faults_.clear("xr.pose_unmeasured", now_ns);
  }
  const std::string where = endpoint().toStdString();
  if (robot_.state() == supervision::PeerState::kGone)
    faults_.raise("robot.gone", "robot at " + where + " gone: no answer for " + supervision::formatDuration(robot_.seconds()),
                  now_ns);
  else if (robot_.state() == supervision::PeerState::kConnected)
    faults_.clear("robot.gone", now_ns);
  if (xr_.state() == supervision::PeerState::kGone)
    faults_.raise("xr.gone", "XR app gone: nothing from it for " + supervision::formatDuration(xr_.seconds()), now_ns);
  else if (xr_.state() == supervision::PeerState::kConnected)
    faults_.clear("xr.gone", now_ns);

  const std::uint32_t foreign = client_->stats().foreign_schema_version;
  if (foreign != 0)
    faults_.raise("link.schema",
                  "the robot speaks link schema v" + std::to_string(foreign) + ", this console v" +
                      std::to_string(link::kSchemaVersion) + ": run the same telesphere version on both",
                  now_ns);

  if (health_ && robot_.state() == supervision::PeerState::kConnected) {
    if (!health_->arm_ok())
      faults_.raise("arm", "arm: " + (health_->fault().empty() ? std::string("not ok") : health_->fault()), now_ns);
    else
      faults_.clear("arm", now_ns);
    if (camera_reconnects_.size() != std::size_t(health_->cameras_size()))
      camera_reconnects_.assign(std::size_t(health_->cameras_size()), 0);
    for (int i = 0; i < health_->cameras_size(); ++i) {
      const auto& c = health_->cameras(i);
      const std::string key = "camera." + std::to_string(i);
      if (!c.last_error().empty())
        faults_.raise(key, "camera " + c.name() + ": " + c.last_error(), now_ns);
      else
        faults_.clear(key, now_ns);
      if (c.reconnects() > camera_reconnects_[std::size_t(i)]) {
        faults_.raise(key + ".reconnect",
                      "camera " + c.name() + " was lost and reopened (" + std::to_string(c.reconnects()) + " times)",
                      now_ns);
        faults_.clear(key + ".reconnect", now_ns);
      }
      camera_reconnects_[std::size_t(i)] = c.reconnects();
    }
  }
  const telemetry::TelemetryCounts& counts = model_.counts();
  const std::uint64_t lost = counts.robot_batches_lost + counts.xr_batches_lost + activity_.telemetry_overflow;
  if (lost > lost_reported_) {
    faults_.raise("telemetry.lost",
                  "telemetry: " + std::to_string(lost) + " batches lost so far (the plots have gaps there)", now_ns);
    faults_.clear("telemetry.lost", now_ns);
    lost_reported_ = lost;
  }
  if (faults_.version() != fault_version_seen_) {
    fault_version_seen_ = faults_.version();
    emit faultsChanged();
  }
}

}  // namespace telesphere::console
