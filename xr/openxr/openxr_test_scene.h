// SPDX-License-Identifier: MIT
/// @brief The deterministic scene `telesphere-xr openxr` shows while no camera images arrive:
///        one double-sphere fisheye (the simulated head's lens scaled to 960×540) looking at a
///        coloured checkerboard image, placed at the nominal head pose. The same scene is
///        rendered offscreen by the Monado integration test to check the swapchain contents.
///
/// Mapping (DESIGN.md §2 with the camera in place of the robot head): at the first valid frame
/// the HMD pose (midpoint of the eyes) with pitch and roll removed (link::withoutPitchAndRoll)
/// becomes T_vr_nom; then
/// T_cam_eye = T_cam_nom · T_vr_nom⁻¹ · T_vr_eye with T_cam_nom = render::kR_optical_view (the nominal
/// view looks along the camera's optical axis).
#pragma once

#include <Eigen/Geometry>

#include "calib/generic_camera.h"
#include "xr/render/source_image.h"

namespace telesphere::xr::openxr {

struct OpenXrTestScene {
  static constexpr int kImageWidth = 960;
  static constexpr int kImageHeight = 540;

  /// The scene's camera model (ds, calibrated for kImageWidth × kImageHeight).
  static calib::GenericCamera camera();
  /// The checkerboard: 40 px squares, red rising left → right, green top → bottom, blue
  /// alternating 64/192 between squares, plus a white cross at the image centre.
  static render::SourceImage image();
};

}  // namespace telesphere::xr::openxr
