// SPDX-License-Identifier: MIT
/// @brief The operator's head without a headset (desktop mode): a pose T_vr_hmd in the VR
///        reference frame moved by keyboard (walk, rise, turn) and mouse (look), first-person
///        style. Pure maths; the window that reads the keys is xr/desktop/desktop_window.h.
///
/// Frames (DESIGN.md §2, OpenXR convention): `vr` is the reference space (STAGE: origin on the
/// floor, y up); `hmd` is the head's view frame (x right, y up, −z forward). At yaw = pitch = 0
/// the head looks along vr −z. The orientation is R_vr_hmd = R_y(yaw) · R_x(pitch), never any
/// roll: positive yaw turns left (counter-clockwise seen from above), positive pitch looks up.
/// Walking happens in the head's yaw frame (forward = where it looks, projected on the floor;
/// pitch does not make it climb); up and down are along vr +y.
#pragma once

#include <Eigen/Geometry>

namespace telesphere::xr::desktop {

/// What the operator holds or moves during one step. Mouse deltas in window screen coordinates
/// (pixels on X11), x to the right, y downwards (window convention), accumulated since the last
/// step; they turn the head only while `look` is set (the button that drags the view is held).
struct VirtualHeadInput {
  bool forward = false, back = false;  ///< walk along / against the horizontal view direction
  bool left = false, right = false;    ///< side steps
  bool up = false, down = false;       ///< along vr ±y
  bool turn_left = false, turn_right = false;  ///< keyboard yaw at turn_rate_rad_s
  bool look_up = false, look_down = false;     ///< keyboard pitch at turn_rate_rad_s
  double mouse_dx_px = 0.0;  ///< > 0: mouse moved right → the head turns right (yaw decreases)
  double mouse_dy_px = 0.0;  ///< > 0: mouse moved down → the head looks down (pitch decreases)
  bool look = false;         ///< mouse deltas count only while this is set
};

struct VirtualHeadSettings {
  double speed_m_s = 0.5;                    ///< walking speed, any direction (> 0)
  double mouse_sensitivity_rad_px = 0.003;   ///< yaw/pitch per pixel of mouse motion (> 0)
  double turn_rate_rad_s = 1.0;              ///< yaw/pitch rate of the turn keys (> 0)
  /// Start (and reset) position p_vr_hmd = (0, start_height, 0): eye height above the STAGE
  /// floor, 1.6 m like HeadTrajectory::demo(); use 0 with a LOCAL reference space.
  double start_height = 1.6;
};

class VirtualHead {
 public:
  /// Pitch is clamped to ±kMaxPitch (89°) so the view never flips over the pole.
  static constexpr double kMaxPitch = 89.0 * 3.14159265358979323846 / 180.0;
  /// Longest time one step integrates: a stalled window (debugger, drag) must not teleport
  /// the head on the next frame.
  static constexpr double kMaxStepS = 0.1;

  /// Settings must be finite with positive speed, sensitivity and turn rate (asserted).
  explicit VirtualHead(const VirtualHeadSettings& settings = {});

  /// Advances by dt_s seconds: position += speed · dt · unit(direction held) (opposite keys
  /// cancel; diagonals are not faster), yaw/pitch += turn rate · dt from the turn keys, then
  /// yaw −= sensitivity · mouse_dx_px and pitch −= sensitivity · mouse_dy_px when `look`.
  /// Yaw wraps to (−π, π], pitch is clamped to [−kMaxPitch, kMaxPitch].
  /// dt_s is clamped to kMaxStepS; dt_s = 0 applies only the mouse. Refuses (returns false and
  /// changes nothing) when dt_s is negative or not finite, or a mouse delta is not finite.
  bool step(const VirtualHeadInput& input, double dt_s);

  /// Back to the start pose: p_vr_hmd = (0, start_height, 0), yaw = pitch = 0.
  void reset();

  /// The head pose T_vr_hmd (maps points from the hmd view frame into vr).
  Eigen::Isometry3d pose() const;

  double yaw() const { return yaw_; }      ///< rad, (−π, π], about vr +y, 0 looks along −z
  double pitch() const { return pitch_; }  ///< rad, [−kMaxPitch, kMaxPitch], > 0 looks up
  const Eigen::Vector3d& position() const { return p_vr_hmd_; }  ///< p_vr_hmd, metres
  const VirtualHeadSettings& settings() const { return settings_; }

 private:
  VirtualHeadSettings settings_;
  Eigen::Vector3d p_vr_hmd_;
  double yaw_ = 0.0;
  double pitch_ = 0.0;
};

}  // namespace telesphere::xr::desktop
