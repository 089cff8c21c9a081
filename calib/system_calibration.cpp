// SPDX-License-Identifier: MIT
/// @brief SystemCalibration consistency checks.
#include "calib/system_calibration.h"

#include <sstream>

namespace telesphere::calib {
namespace {

std::optional<std::string> transformProblem(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) return "contains a non-finite number";
  const Eigen::Matrix3d R = T.linear();
  const double err = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (err > 1e-6 || R.determinant() < 0) {
    std::ostringstream os;
    os << "rotation is not orthonormal with determinant +1 (|RᵀR − I| = " << err
       << ", det = " << R.determinant() << ")";
    return os.str();
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::pair<std::string, std::string>> SystemCalibration::inconsistency() const {
  using Problem = std::pair<std::string, std::string>;
  if (cameras.empty() || cameras.size() > 2)
    return Problem{"cameras", "telesphere takes one camera or a stereo pair (cam_l, cam_r); got " +
                                  std::to_string(cameras.size())};
  const char* const labels[] = {"cam_l", "cam_r"};
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const auto& cam = cameras[i];
    const std::string field = "cameras[" + std::to_string(i) + "]";
    if (cam.label != labels[i])
      return Problem{field + ".label", "is \"" + cam.label + "\", expected \"" + labels[i] + "\""};
    if (cam.width <= 0 || cam.height <= 0 || cam.width > 32768 || cam.height > 32768)
      return Problem{field + ".resolution", std::to_string(cam.width) + "x" +
                                                std::to_string(cam.height) +
                                                " is not an image size in (0, 32768]"};
    const Eigen::VectorXd p = cam.camera.params();
    if (p[2] < -0.5 || p[2] > cam.width - 0.5 || p[3] < -0.5 || p[3] > cam.height - 0.5) {
      std::ostringstream os;
      os << "principal point (" << p[2] << ", " << p[3] << ") lies outside the " << cam.width
         << "x" << cam.height << " image";
      return Problem{field + ".intrinsics", os.str()};
    }
  }
  if (cameras.size() == 2 && !T_cam_l_cam_r)
    return Problem{"extrinsics.T_cam_l_cam_r", "missing: a stereo pair needs it"};
  if (cameras.size() == 1 && T_cam_l_cam_r)
    return Problem{"extrinsics.T_cam_l_cam_r", "given, but there is only one camera"};
  const std::pair<const char*, const std::optional<Eigen::Isometry3d>*> transforms[] = {
      {"T_cam_l_cam_r", &T_cam_l_cam_r},
      {"T_flange_cam_l", &T_flange_cam_l},
      {"T_robot_mount", &T_robot_mount},
      {"T_wrist_marker", &T_wrist_marker}};
  for (const auto& [name, T] : transforms)
    if (*T)
      if (auto problem = transformProblem(**T))
        return Problem{std::string("extrinsics.") + name, *problem};
  return std::nullopt;
}

}  // namespace telesphere::calib
