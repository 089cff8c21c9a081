// SPDX-License-Identifier: MIT
/// @brief handEyeSampleOf (see hand_eye_sample.h).
#include "console/calibration/hand_eye_sample.h"

#include "calib/target_detection.h"
#include "console/calibration/stereo_sample.h"
#include "robot/link/link_pose.h"

namespace telesphere::console::calibration {
namespace {

/// "" when [before, after] brackets t within max_ns, else why not.
std::string bracketProblem(const char* arm, std::int64_t t, std::int64_t before, std::int64_t after, std::int64_t max_ns) {
  if (before == 0 || after == 0) return std::string("the ") + arm + "'s joint states around the capture time are missing";
  if (!(before <= t && t <= after))
    return std::string("the ") + arm + "'s joint states do not bracket the capture time (" +
           std::to_string((before - t) / 1000) + " µs .. " + std::to_string((after - t) / 1000) + " µs from it)";
  if (after - before > max_ns)
    return std::string("the ") + arm + "'s joint states around the capture time are " +
           std::to_string((after - before) / 1'000'000) + " ms apart (reports lost; at most " +
           std::to_string(max_ns / 1'000'000) + " ms)";
  return "";
}

}  // namespace

std::optional<HandEyeStillSample> handEyeSampleOf(const link::proto::CalibrationStill& still, const WristMarker& marker,
                                                  std::string* reason, const HandEyeSampleOptions& options) {
  const std::int64_t t = still.capture_ns();
  if (still.manipulator_joints_size() == 0 || !still.has_t_mount_wrist()) {
    *reason = "the robot reports no manipulator joints (is the manipulator connected? in simulation: --sim-manipulator)";
    return std::nullopt;
  }
  if (!still.has_t_robot_flange()) {
    *reason = "the still carries no head-arm pose";
    return std::nullopt;
  }
  for (const std::string& problem :
       {bracketProblem("head arm", t, still.joints_before_ns(), still.joints_after_ns(), options.max_bracket_ns),
        bracketProblem("manipulator", t, still.manipulator_before_ns(), still.manipulator_after_ns(),
                       options.max_bracket_ns)}) {
    if (!problem.empty()) {
      *reason = problem;
      return std::nullopt;
    }
  }
  HandEyeStillSample out;
  out.sequence = still.sequence();
  out.sample.t_ns = t;
  out.sample.T_robot_flange = link::fromLinkPose(still.t_robot_flange());
  out.sample.T_mount_wrist = link::fromLinkPose(still.t_mount_wrist());
  calib::DetectionOptions detection;
  detection.border_margin_px = options.border_margin_px;
  const link::proto::CalibrationImage* images[2] = {&still.left(), &still.right()};
  for (std::size_t c = 0; c < 2; ++c) {
    const calib::GrayImage image = grayImageOf(*images[c]);
    if (image.pixels.empty()) continue;
    out.width = image.width;
    out.height = image.height;
    (c == 0 ? out.sample.corners_l : out.sample.corners_r) =
        calib::detectArucoMarker(image, marker.dictionary, marker.id, detection);
    out.thumbnails[c] = thumbnailOf(image, options.thumbnail_width);
  }
  if (out.width == 0) {
    *reason = "the still's images are empty or their sizes do not match their bytes";
    return std::nullopt;
  }
  if (!out.sample.corners_l && !out.sample.corners_r) {
    *reason = "marker " + std::to_string(marker.id) + " (" + marker.dictionary + ") is in neither image";
    return std::nullopt;
  }
  return out;
}

}  // namespace telesphere::console::calibration
