// SPDX-License-Identifier: MIT
/// @brief Records, for chosen display frames, what each eye pixel showed — the camera pixel it
///        sampled (the projection map, StereoViewRenderer::renderProjectionMap) — beside the head
///        pose, the eye geometry, the mapping, the mode and radius and the camera frame shown: all
///        the ground-truth check (app/bench/truth) needs to follow every eye pixel back into the scene
///        and compare it with what the eye should have seen. Offscreen mode only (--truth-out).
///
/// Files in the folder: `frames.csv`, one row per recorded frame (columns in the header: index,
/// display_ns (XR clock), stereo_sequence, capture_ns (robot clock), mode, radius_m, ipd_m,
/// fov_left … fov_down (rad), width, height (eye, px), image_width, image_height (camera, px), then the poses hmd_* (T_vr_hmd), robot_vr_*
/// (T_robot_vr used), cam_left_* and cam_right_* (T_robot_cam as stamped in the frame) as
/// tx ty tz qx qy qz qw), and `map_<index>.f32`: float32 little-endian, left eye then right eye,
/// rows top first, (x, y) camera pixel per eye pixel, NaN where the eye pixel shows no camera pixel.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>

#include "shaders/offscreen_target.h"
#include "xr/render/eye_view.h"
#include "xr/frame_loop/operator_view.h"

namespace telesphere::xr::frame_loop {

class ProjectionMapRecorder {
 public:
  /// Creates `dir` (if needed) and frames.csv; nothing, with the reason, when it cannot. Needs a
  /// current GL context (it makes two float targets of the eye size).
  static std::unique_ptr<ProjectionMapRecorder> open(const std::string& dir, int eye_width, int eye_height,
                                                     std::string* error);

  /// Records the frame the view just rendered for these eye poses (T_vr_hmd · T_hmd_eye); false
  /// with the reason on a GL or file error. Frames before the first camera image are skipped.
  bool record(OperatorView& view, std::int64_t display_ns, const Eigen::Isometry3d& T_vr_hmd,
              const Eigen::Isometry3d T_hmd_eye[2], double ipd, const render::EyeView& eye, std::string* error);
  std::uint64_t recorded() const { return index_; }

 private:
  ProjectionMapRecorder(std::string dir, std::ofstream csv, int width, int height);

  std::string dir_;
  std::ofstream csv_;
  gl::OffscreenTarget target_;
  std::uint64_t index_ = 0;
};

}  // namespace telesphere::xr::frame_loop
