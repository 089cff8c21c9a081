// SPDX-License-Identifier: MIT
/// @brief Which camera frame and head pose each eyes PNG shows: `telesphere-xr offscreen
///        --png-every N` writes `views.csv` beside its PNGs, one row per PNG, and the offline
///        replay renders the same views from the session's recording (`--replay FILE --views
///        views.csv`), so a replay is checked against what the operator saw live, not only
///        against another replay. Rows: `png,stereo_sequence,px,py,pz,qx,qy,qz,qw` (T_vr_hmd, m
///        and a unit quaternion), doubles with 17 significant digits so the pose round-trips
///        exactly, then the link's cues the operator saw over it (link_state_overlay.h):
///        `image_saturation,link_age_ms,eye_camera_distance_m,stream_text,insecure_link` (0|1:
///        "INSECURE LINK" was shown). Files written before the last column, or before all five,
///        still load (no insecure warning; no cues).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "xr/frame_loop/link_state_overlay.h"

namespace telesphere::xr::frame_loop {

struct LoggedView {
  std::string png;                   ///< file name beside views.csv, e.g. eyes_00010.png
  std::uint64_t stereo_sequence = 0;  ///< the camera frame on show (StereoFrame.sequence)
  Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();  ///< the head pose both eyes were rendered for
  float image_saturation = 1.0f;  ///< the image's saturation (0: shown grey, too old)
  LinkState link_state;           ///< the cues drawn over both eyes
};

/// The file's name in a PNG folder.
inline constexpr const char* kLoggedViewsFile = "views.csv";

/// Appends one row to `path` (the header first when the file is new or empty); false with the reason.
bool appendLoggedView(const std::string& path, const LoggedView& view, std::string* error);

/// The rows of a views file; nothing, with the file, line and reason, when it is not one (a file
/// name with a path or a comma, a sequence that is not a number, a pose that is not finite or a
/// quaternion far from unit length).
std::optional<std::vector<LoggedView>> loadLoggedViews(const std::string& path, std::string* error);

}  // namespace telesphere::xr::frame_loop
