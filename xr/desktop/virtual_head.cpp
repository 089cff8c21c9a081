// SPDX-License-Identifier: MIT
/// @brief VirtualHead: yaw/pitch and position integrated from keyboard and mouse input.
#include "xr/desktop/virtual_head.h"

#include <algorithm>
#include <cmath>

#include "calib/debug_assert.h"

namespace telesphere::xr::desktop {
namespace {

constexpr double kVirtualHeadPi = 3.14159265358979323846;

/// Wraps an angle to (−π, π].
double wrapVirtualHeadYaw(double yaw) {
  const double wrapped = std::remainder(yaw, 2.0 * kVirtualHeadPi);  // [−π, π]
  return wrapped <= -kVirtualHeadPi ? kVirtualHeadPi : wrapped;
}

double virtualHeadAxis(bool positive, bool negative) {
  return (positive ? 1.0 : 0.0) - (negative ? 1.0 : 0.0);
}

}  // namespace

VirtualHead::VirtualHead(const VirtualHeadSettings& settings) : settings_(settings) {
  TS_ASSERT(std::isfinite(settings.speed_m_s) && settings.speed_m_s > 0.0, settings.speed_m_s);
  TS_ASSERT(std::isfinite(settings.mouse_sensitivity_rad_px) &&
                settings.mouse_sensitivity_rad_px > 0.0,
            settings.mouse_sensitivity_rad_px);
  TS_ASSERT(std::isfinite(settings.turn_rate_rad_s) && settings.turn_rate_rad_s > 0.0,
            settings.turn_rate_rad_s);
  TS_ASSERT(std::isfinite(settings.start_height), settings.start_height);
  reset();
}

void VirtualHead::reset() {
  p_vr_hmd_ = Eigen::Vector3d(0.0, settings_.start_height, 0.0);
  yaw_ = 0.0;
  pitch_ = 0.0;
}

bool VirtualHead::step(const VirtualHeadInput& input, double dt_s) {
  if (!std::isfinite(dt_s) || dt_s < 0.0) return false;
  if (!std::isfinite(input.mouse_dx_px) || !std::isfinite(input.mouse_dy_px)) return false;
  const double dt = std::min(dt_s, kMaxStepS);

  // Keyboard turns first, so that a step walks in the direction the head has at its end.
  double yaw = yaw_ + settings_.turn_rate_rad_s * dt * virtualHeadAxis(input.turn_left, input.turn_right);
  double pitch =
      pitch_ + settings_.turn_rate_rad_s * dt * virtualHeadAxis(input.look_up, input.look_down);
  if (input.look) {
    yaw -= settings_.mouse_sensitivity_rad_px * input.mouse_dx_px;
    pitch -= settings_.mouse_sensitivity_rad_px * input.mouse_dy_px;
  }
  // A finite but huge mouse delta times the sensitivity can still overflow to ±inf.
  if (!std::isfinite(yaw) || !std::isfinite(pitch)) return false;
  yaw_ = wrapVirtualHeadYaw(yaw);
  pitch_ = std::clamp(pitch, -kMaxPitch, kMaxPitch);

  // Walking in the yaw frame: forward_vr = R_y(yaw)·(0, 0, −1), right_vr = R_y(yaw)·(1, 0, 0).
  const double s = std::sin(yaw_), c = std::cos(yaw_);
  const Eigen::Vector3d forward_vr(-s, 0.0, -c);
  const Eigen::Vector3d right_vr(c, 0.0, -s);
  const Eigen::Vector3d direction_vr = virtualHeadAxis(input.forward, input.back) * forward_vr +
                                       virtualHeadAxis(input.right, input.left) * right_vr +
                                       virtualHeadAxis(input.up, input.down) * Eigen::Vector3d::UnitY();
  const double norm = direction_vr.norm();
  if (norm > 0.0) p_vr_hmd_ += (settings_.speed_m_s * dt / norm) * direction_vr;
  return true;
}

Eigen::Isometry3d VirtualHead::pose() const {
  Eigen::Isometry3d T_vr_hmd = Eigen::Isometry3d::Identity();
  T_vr_hmd.linear() = (Eigen::AngleAxisd(yaw_, Eigen::Vector3d::UnitY()) *
                       Eigen::AngleAxisd(pitch_, Eigen::Vector3d::UnitX()))
                          .toRotationMatrix();
  T_vr_hmd.translation() = p_vr_hmd_;
  return T_vr_hmd;
}

}  // namespace telesphere::xr::desktop
