// SPDX-License-Identifier: MIT
/// @brief The console's connection to the system, without widgets (DESIGN.md §1, §7): one
///        LinkClient to the robot (which relays the XR app), polled on the GUI thread every
///        poll_ms without ever blocking it. Each poll takes every telemetry batch into the
///        series (at source time), the newest health, state and XR stats, the newest camera
///        preview, updates whether robot and XR app are there, and raises or clears faults.
///        Control requests go out on a worker (link::ControlQueue); their outcome comes back on
///        the GUI thread, to the caller's callback and the control log. The widgets only show
///        what this holds and forward what the supervisor does.
#pragma once

#include <QImage>
#include <QObject>
#include <QString>
#include <QTimer>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "console/supervision/connection_monitor.h"
#include "console/supervision/fault_log.h"
#include "console/telemetry/series_store.h"
#include "console/telemetry/telemetry_model.h"
#include "robot/link/control_queue.h"
#include "robot/link/link_client.h"

namespace telesphere::console {

struct ConsoleSessionOptions {
  link::LinkEndpoints endpoints;
  supervision::PeerThresholds robot{1'000'000'000, 5'000'000'000};
  supervision::PeerThresholds xr{1'500'000'000, 5'000'000'000};  ///< the XR app is heard through the robot
  int poll_ms = 20;
  double retention_s = 600.0;  ///< seconds of every series kept (the longest plot window)
  std::chrono::milliseconds control_timeout{2000};
};

/// One control request and what came of it.
struct ControlOutcome {
  QString what;             ///< "set_jpeg_quality 80", …
  bool answered = false;    ///< false: no reply within the timeout
  bool ok = false;
  QString error;            ///< the robot's text when refused
  link::proto::ControlReply reply;
  double sent_s = 0, replied_s = 0;  ///< plot clock
  /// "set_jpeg_quality 80: ok", "nominal capture: refused: no fresh head pose …", …
  QString text() const;
};

/// The newest camera preview, decoded.
struct CameraPreview {
  QImage left, right;
  std::uint64_t sequence = 0;
  double capture_s = 0;  ///< plot clock
  int source_width = 0, source_height = 0;
};

class ConsoleSession : public QObject {
  Q_OBJECT

 public:
  explicit ConsoleSession(const ConsoleSessionOptions& options, QObject* parent = nullptr);
  ~ConsoleSession() override;

  const ConsoleSessionOptions& options() const { return options_; }
  QString endpoint() const;  ///< where the robot is expected ("tcp://127.0.0.1:5760")

  telemetry::SeriesStore& series() { return series_; }
  const telemetry::SeriesStore& series() const { return series_; }
  const telemetry::TelemetryModel& telemetry() const { return model_; }
  const supervision::FaultLog& faults() const { return faults_; }
  void acknowledgeFaults();
  const supervision::PeerMonitor& robot() const { return robot_; }
  const supervision::PeerMonitor& xr() const { return xr_; }

  const std::optional<link::proto::RobotHealth>& health() const { return health_; }
  const std::optional<link::proto::RobotState>& robotState() const { return state_; }
  const std::optional<link::proto::XrStats>& xrStats() const { return xr_stats_; }
  std::optional<link::ClockSync::Estimate> clock() const { return client_->clock().estimate(); }
  const link::LinkActivity& activity() const { return activity_; }
  link::LinkStatsSnapshot linkStats() const { return client_->stats(); }
  const CameraPreview& preview() const { return preview_; }
  bool everHeardRobot() const { return activity_.robot_pong_ns != 0; }

  /// The plot clock now (s since the session started).
  double now() const;
  /// Plots that are paused keep their data: nothing newer than `t` is trimmed (none: live).
  void holdDataFrom(std::optional<double> t) { hold_from_ = t; }

  /// Sends `request` (never blocks); `done` runs on the GUI thread with the outcome.
  void request(link::proto::ControlRequest request, const QString& what,
               std::function<void(const ControlOutcome&)> done = {});

  /// Called on the GUI thread with every telemetry envelope as it is taken from the link, and the
  /// robot → console clock offset then (none before the first pong): a study keeps its trials'.
  using TelemetryTap =
      std::function<void(const link::proto::Envelope& envelope, std::optional<std::int64_t> robot_to_console_ns)>;
  void setTelemetryTap(TelemetryTap tap) { tap_ = std::move(tap); }

  /// One poll now (the timer's work; tests call it to step without waiting).
  void poll();

 signals:
  void updated();         ///< after every poll
  void previewChanged();  ///< a new preview was decoded
  void faultsChanged();
  void controlAnswered(const QString& text);
  /// A request the robot accepted, at its reply time (plot clock), for markers in the graphs.
  void controlAccepted(double t, const QString& what);

 private:
  void updateFaults(std::int64_t now_ns);

  ConsoleSessionOptions options_;
  std::int64_t origin_ns_;
  std::unique_ptr<link::LinkClient> client_;
  telemetry::SeriesStore series_;
  telemetry::TelemetryModel model_;
  supervision::FaultLog faults_;
  supervision::PeerMonitor robot_, xr_;
  std::optional<link::proto::RobotHealth> health_;
  std::optional<link::proto::RobotState> state_;
  std::optional<link::proto::XrStats> xr_stats_;
  link::LinkActivity activity_;
  CameraPreview preview_;
  std::optional<double> hold_from_;
  TelemetryTap tap_;
  std::vector<std::uint64_t> camera_reconnects_;
  std::uint64_t lost_reported_ = 0;
  std::uint64_t fault_version_seen_ = 0;
  QTimer timer_;
  std::unique_ptr<link::ControlQueue> control_;  ///< last: stops before what its replies touch
};

}  // namespace telesphere::console
