// SPDX-License-Identifier: MIT
/// @brief What the calibration procedures ask of the robot, over the link (issue #15): hold the
///        head at a pose and wait until it has settled there, take a full-resolution stereo
///        still, release the head. Synchronous (call it from a worker thread, never from the
///        GUI thread); every failure says why.
///
///        A hold is a lease (link HeadHold): while this object holds the head, a thread of its own
///        renews it every kRenewPeriod; when this object goes away (or its process dies) the
///        renewals stop and the robot releases the head within its lease (2 s). A hold the robot
///        ended (the console's "release head", an expired lease, a robot restart) is reported by
///        holdLost() and fails the next wait.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "calib/system_calibration.h"
#include "robot/link/link_client.h"

namespace telesphere::console::calibration {

struct SettleOptions {
  double position_tolerance_m = 0.002;  ///< of the pose asked for
  double angle_tolerance_deg = 0.5;
  double still_position_m = 0.0002;     ///< moved less than this between two robot states…
  double still_angle_deg = 0.03;
  int still_states = 5;                 ///< …this many states in a row (50 Hz: 0.1 s)
  std::chrono::milliseconds timeout{10000};
};

class CalibrationRobot {
 public:
  static constexpr std::chrono::milliseconds kRenewPeriod{500};

  /// `holder`: who holds the head, as the supervisor reads it in the console ("hand-eye wizard
  /// (headless)"); the process id and host are added.
  explicit CalibrationRobot(link::LinkClient& client, const std::string& holder = "telesphere-console",
                            std::chrono::milliseconds request_timeout = std::chrono::seconds(3));
  ~CalibrationRobot();  ///< releases the head if this object held it
  CalibrationRobot(const CalibrationRobot&) = delete;
  CalibrationRobot& operator=(const CalibrationRobot&) = delete;

  /// The name the robot shows for this object's holds ("hand-eye wizard (headless), pid 4242 on rig-pc").
  const std::string& holder() const { return holder_; }
  /// Why the robot no longer holds the head for this object (it ended the hold itself); empty
  /// while the hold stands or none was asked for.
  std::string holdLost() const;

  /// Asks the robot to hold the head at T_robot_head; false with the robot's reason.
  bool holdHeadAt(const Eigen::Isometry3d& T_robot_head, std::string* error);
  /// Waits until the reported head pose is at T_robot_head and still; false with the reason
  /// (timeout with the remaining distance, cancelled).
  bool waitSettled(const Eigen::Isometry3d& T_robot_head, const SettleOptions& options,
                   const std::atomic<bool>* cancel, std::string* error);
  /// Asks the robot to move the head along the sinusoidal calibration pattern about the nominal
  /// pose (hand-eye samples); false with the robot's reason.
  bool runHeadPattern(double amplitude_deg, std::string* error);
  /// Takes the head back to T_robot_head (where a wizard's run found it) and waits until it has
  /// settled there; not cancellable (a cancelled run returns it too, within options.timeout).
  /// False with the reason. The hold stays: release() afterwards.
  bool returnHeadTo(const Eigen::Isometry3d& T_robot_head, const SettleOptions& options, std::string* error);
  /// Gives the head back to the operator.
  bool release(std::string* error);

  /// A full-resolution stereo still (the robot's calibration_capture; the reply may take as long
  /// as the robot's --still-timeout-ms, so the wait here is `still_timeout`).
  std::optional<link::proto::CalibrationStill> takeStill(std::string* error);
  void setStillTimeout(std::chrono::milliseconds timeout) { still_timeout_ = timeout; }

  /// The calibration the robot uses now (get_calibration).
  std::optional<link::proto::CalibrationInUse> calibrationInUse(std::string* error);
  /// Makes the robot use `calibration` from now on (apply_calibration; the XR app follows); the
  /// calibration in use after it, or nothing with the robot's reason.
  std::optional<link::proto::CalibrationInUse> applyCalibration(const calib::SystemCalibration& calibration,
                                                                const std::string& source, std::string* error);
  /// Back to the calibration before the last apply (revert_calibration).
  std::optional<link::proto::CalibrationInUse> revertCalibration(std::string* error);

  /// The newest robot state's head pose (waits up to `timeout` for a first state).
  std::optional<Eigen::Isometry3d> headPose(std::chrono::milliseconds timeout);

 private:
  std::optional<link::proto::ControlReply> request(link::proto::ControlRequest r, std::string* error,
                                                   std::optional<std::chrono::milliseconds> timeout = std::nullopt);
  /// A get/apply/revert_calibration request: the calibration in use after it.
  std::optional<link::proto::CalibrationInUse> calibrationRequest(link::proto::ControlRequest r, std::string* error);
  /// A hold request (pose or pattern) under this object's lease; starts the renewals.
  bool hold(link::proto::ControlRequest r, std::string* error);
  void renewals();
  void stopRenewals();

  link::LinkClient& client_;
  std::string holder_;
  std::chrono::milliseconds request_timeout_;
  std::chrono::milliseconds still_timeout_{std::chrono::seconds(65)};  ///< above the robot's largest

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::uint64_t lease_ = 0;  ///< the hold this object has (0: none)
  std::string lost_;         ///< why the robot ended it
  bool stopping_ = false;
  std::thread renewer_;
};

}  // namespace telesphere::console::calibration
