// SPDX-License-Identifier: MIT
/// @brief XArmHeadArm: the real UFACTORY xArm 6 as the head arm (HeadArm seam), over the
///        controller's own TCP protocol (robot/arm/xarm/: command port 502, real-time report port
///        30003). `telesphere-robot --arm xarm --arm-address IP` drives it; robot/arm/xarm/README.md
///        is the lab's step-by-step guide.
///
/// Start-up (start()): connect both ports; read the firmware version and from then on speak the
/// protocol identifier that firmware expects (3 from 1.8.6 on, else 2; a reply must carry its
/// request's); read the serial number; time round trips of
/// "get state" (the one-way link delay is half the fastest); read the error and warning codes and
/// refuse to go on while the controller has an error, unless the supervisor asked to clear them
/// (options.clear_errors, `--arm-clear-errors`); set the head's payload and the collision
/// sensitivity when configured and read back what the controller uses from its normal report
/// (port 30001): a payload or sensitivity other than the configured one stops the start-up with
/// both values (a wrong head mass would otherwise surface as a "mystery" C31 collision later);
/// enable the motors; in position mode, move to the
/// nominal joints at a limited speed and wait until the reports show them; switch to servo mode
/// and wait until the reports show it. Then update() and sendTarget() stream servo joint targets.
/// While it waits (the nominal move takes up to 30 s), a "get state" every keepalive keeps the
/// command connection in use, as a controller speaking identifier 3 expects.
///
/// Joint states: every report (100 Hz) becomes a JointState stamped on our steady clock. The
/// report has no time stamp, so the stamp is its arrival time, fitted to the report's own period
/// by the lower envelope of (report index × 10 ms, arrival) pairs (DeviceClockMapping: the
/// fastest arrivals carry the fit, delays from scheduling only ever add), minus the one-way link
/// delay measured at start-up.
///
/// Safety: a target outside the joint limits, not finite, or further from the previous target
/// than the joints' top speed (180°/s) allows in the time since is refused (sendTarget false);
/// ten refused jumps in a row stop streaming with a fault that says which joint jumped. No
/// report for report_silence_limit, no reply to servo commands for reply_silence_limit, or a
/// connection closed or malformed: streaming stops, status kDisconnected, the reason in
/// faultText(). A controller error (reply status bit, or the reports' state "stopped") stops
/// streaming with kStopped and the controller's code as text ("C31 collision caused abnormal
/// current"). Nothing reconnects or clears by itself: clearStop() (the console's "clear fault")
/// does, and only then.
///
/// Thread-safety: update(), sendTarget(), pollState(), stop() and clearStop() from the head loop's
/// thread; status(), faultText() and stats() from any thread. Two threads of its own receive the
/// replies and the reports.
#pragma once

#include <array>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "robot/clock/clock.h"
#include "robot/arm/head_arm.h"

namespace telesphere::robot::arm {

struct XArmOptions {
  std::string address;  ///< the controller's IPv4 address
  int command_port = 502;
  int report_port = 30003;
  int normal_report_port = 30001;  ///< 5 Hz reports with the payload and sensitivities (read back at start-up)
  /// The head's payload: mass (kg) and centre of mass in the tool frame (mm); nothing: the
  /// controller keeps what it has (read back and reported anyway).
  std::optional<double> payload_kg;
  std::array<double, 3> payload_com_mm{0.0, 0.0, 0.0};
  /// 0 (off) … 5 (most sensitive); nothing: the controller keeps its own.
  std::optional<int> collision_sensitivity;
  std::chrono::milliseconds keepalive{1000};              ///< a request at least this often while waiting
  std::chrono::milliseconds connect_timeout{3000};
  std::chrono::milliseconds reply_timeout{2000};          ///< a start-up request without its reply fails
  std::chrono::milliseconds report_silence_limit{100};    ///< 10 report periods
  std::chrono::milliseconds reply_silence_limit{300};     ///< an unanswered servo command
  /// Clear the controller's errors and warnings at start-up (only when the supervisor asks).
  bool clear_errors = false;
  /// Moved to in position mode before streaming (rad); nothing: streaming starts where the arm is.
  std::optional<JointVector> nominal_q;
  double nominal_speed = 0.35;         ///< rad/s (20°/s) for that move
  double nominal_acceleration = 1.0;   ///< rad/s²
  std::chrono::milliseconds nominal_timeout{30000};
  double max_velocity = 3.14159265358979323846;  ///< rad/s: the xArm 6's top joint speed (jump limit)
  int refused_jumps_for_fault = 10;
  int link_delay_samples = 10;
  std::int64_t report_period_ns = 10'000'000;    ///< port 30003: 100 Hz
};

class XArmHeadArm final : public HeadArm {
 public:
  /// Connects and prepares the arm (file comment). Null with the reason (which step, the
  /// controller's words) on failure. `progress` (optional) hears each step as it starts.
  static std::unique_ptr<XArmHeadArm> start(const XArmOptions& options, const clock::Clock& clock, std::string* error,
                                            const std::function<void(const std::string&)>& progress = {});
  ~XArmHeadArm() override;
  XArmHeadArm(const XArmHeadArm&) = delete;
  XArmHeadArm& operator=(const XArmHeadArm&) = delete;

  void update() override;
  bool sendTarget(const JointVector& q_target) override;
  std::optional<JointState> pollState() override;
  ArmStatus status() const override;
  void stop() override;
  bool clearStop() override;
  std::string faultText() const override;

  struct Stats {
    std::string firmware;            ///< as register 1 answered
    std::string serial;              ///< the arm's (register 2), empty if it did not answer
    std::uint16_t protocol = 2;      ///< the identifier spoken (3 from firmware 1.8.6 on)
    double link_delay_ms = 0;        ///< one way, from the fastest start-up round trip
    std::uint64_t reports = 0;
    std::uint64_t targets_sent = 0;
    std::uint64_t replies = 0;
    std::uint64_t refused_limits = 0;  ///< not finite or outside the joint limits
    std::uint64_t refused_jumps = 0;
    std::uint64_t reconnects = 0;
    double report_drift_ppm = 0;     ///< the report clock against ours
    /// Arrival jitter of the reports: the 99th percentile of |interval − period| over the last
    /// 1000 intervals, ms.
    double report_jitter_ms_p99 = 0;
    /// What the controller reported it uses (normal report, read at start-up and reconnect).
    bool payload_read = false;
    double payload_kg = 0;
    std::array<double, 3> payload_com_mm{};
    int collision_sensitivity = -1;
    std::string readback_error;      ///< why nothing was read back (empty: it was)
  };
  Stats stats() const;

 private:
  struct Impl;
  explicit XArmHeadArm(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace telesphere::robot::arm
