// SPDX-License-Identifier: MIT
/// @brief One hand-eye sample from a stereo still (issue #15, paper eqs. 1–3): the wrist
///        marker's corners in each camera at full resolution, the head arm's and the
///        manipulator's forward kinematics at the images' capture time, and thumbnails for the
///        sample list. Freshness is checked here: a still whose joint states do not bracket its
///        capture time (for either arm), or bracket it across a gap wider than two reports, is
///        refused with the reason, as is a still without manipulator joints or without the
///        marker in either camera.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "calib/gray_image.h"
#include "calib/hand_eye_calibration.h"
#include "robot/link/telesphere_link.pb.h"

namespace telesphere::console::calibration {

/// The ArUco marker on the manipulator's wrist.
struct WristMarker {
  std::string dictionary = "DICT_4X4_50";
  int id = 0;
  double size_m = 0.1;
};

struct HandEyeStillSample {
  std::uint64_t sequence = 0;   ///< the stereo frame's sequence on the link
  calib::HandEyeSample sample;  ///< t_ns, T_robot_flange, T_mount_wrist, corners (px)
  std::array<calib::GrayImage, 2> thumbnails;
  int width = 0, height = 0;    ///< full resolution
};

struct HandEyeSampleOptions {
  /// Widest bracket of joint states around the capture time: two 100 Hz reports (a wider one
  /// means reports were lost and the joints in between are a guess).
  std::int64_t max_bracket_ns = 20'000'000;
  int thumbnail_width = 160;
  double border_margin_px = 4.0;
};

/// The sample of `still`, or nothing with the reason in *reason.
std::optional<HandEyeStillSample> handEyeSampleOf(const link::proto::CalibrationStill& still, const WristMarker& marker,
                                                  std::string* reason, const HandEyeSampleOptions& options = {});

}  // namespace telesphere::console::calibration
