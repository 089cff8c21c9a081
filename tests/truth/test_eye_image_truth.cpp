// SPDX-License-Identifier: MIT
/// @brief The ground-truth check itself, without processes: projection maps made by the double
///        reference renderer (xr/render/reference_renderer.h) for known poses in the default scene. Eyes
///        at the cameras see the scene where it is (error ≈ 0, only the float32 map's rounding);
///        an eye 5 cm off the camera sees the sphere's distortion γ; a frame stamped with a pose
///        5 mm off the truth is caught; bad files are refused with their line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "calib/calibration_file.h"
#include "calib/camera_resolution.h"
#include "app/bench/truth/eye_image_truth.h"
#include "xr/render/reference_renderer.h"

namespace telesphere::truth {
namespace {

struct TruthRig {
  calib::SystemCalibration calibration;
  robot::cameras::SyntheticScene scene = robot::cameras::defaultScene();
  RobotTruthRow robot;
  XrTruthFrame frame;

  TruthRig() {
    auto loaded = calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
    EXPECT_TRUE(loaded) << loaded.error().describe();
    calibration = *loaded;
    // The left camera at the default scene's head position looking along the robot's +x
    // (optical z = robot x, optical x = robot −y, optical y = robot −z); the right one 64 mm to its right.
    Eigen::Isometry3d T_robot_cam_l = Eigen::Isometry3d::Identity();
    T_robot_cam_l.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    T_robot_cam_l.translation() = robot::cameras::DefaultSceneLayout{}.head_position + Eigen::Vector3d(0, 0.032, 0);
    const Eigen::Isometry3d T_robot_cam_r = T_robot_cam_l * *calibration.T_cam_l_cam_r;
    robot.sequence = 7;
    robot.capture_ns = {1'000'000'000, 1'000'000'000};
    robot.T_robot_cam_true = {T_robot_cam_l, T_robot_cam_r};
    robot.mapping_set = true;
    robot.T_robot_vr = Eigen::Isometry3d::Identity();
    frame.index = 1;
    frame.stereo_sequence = 7;
    frame.mode = "full6d";
    frame.radius_m = 1.0;
    frame.ipd_m = calibration.T_cam_l_cam_r->translation().norm();
    frame.fov = {-0.6, 0.6, 0.5, -0.5};
    frame.width = 96;
    frame.height = 80;
    frame.image_width = 320;
    frame.image_height = 180;
    frame.T_robot_cam_stamped = {T_robot_cam_l, T_robot_cam_r};
    frame.T_vr_hmd = headAtCameras();
  }

  /// The head pose that puts each eye at its camera, looking along the camera axis.
  Eigen::Isometry3d headAtCameras() const {
    Eigen::Isometry3d T_hmd_eye_l = Eigen::Isometry3d::Identity();
    T_hmd_eye_l.translation().x() = -0.5 * frame.ipd_m;
    return *robot.T_robot_cam_true[0] * Eigen::Isometry3d(xr::render::kR_optical_view) * T_hmd_eye_l.inverse();
  }

  /// The maps the renderer would make from the frame's stamped poses (double reference, stored
  /// as float32 like the GPU's).
  std::vector<float> maps() const {
    std::vector<float> out(static_cast<std::size_t>(frame.width) * frame.height * 4, std::nanf(""));
    xr::render::RenderSettings settings;
    settings.radius = frame.radius_m;
    for (int eye = 0; eye < 2; ++eye) {
      std::string error;
      const auto camera = calib::atResolution(calibration.cameras[eye], frame.image_width, frame.image_height, &error);
      EXPECT_TRUE(camera) << error;
      Eigen::Isometry3d T_hmd_eye = Eigen::Isometry3d::Identity();
      T_hmd_eye.translation().x() = (eye == 0 ? -0.5 : 0.5) * frame.ipd_m;
      xr::render::EyeView view;
      view.fov = frame.fov;
      view.width = frame.width;
      view.height = frame.height;
      view.T_cam_eye = frame.T_robot_cam_stamped[eye].inverse() * frame.T_robot_vr_used * frame.T_vr_hmd * T_hmd_eye;
      for (int row = 0; row < frame.height; ++row)
        for (int col = 0; col < frame.width; ++col) {
          const auto px = xr::render::referenceCameraPixel(camera->camera, frame.image_width, frame.image_height, view,
                                                   settings, col, row);
          if (!px) continue;
          const std::size_t i = (static_cast<std::size_t>(eye) * frame.width * frame.height +
                                 static_cast<std::size_t>(row) * frame.width + col) * 2;
          out[i] = static_cast<float>(px->x());
          out[i + 1] = static_cast<float>(px->y());
        }
    }
    return out;
  }

  FrameEyeError evaluate() const {
    std::string error;
    const auto result = evaluateEyeImages(frame, maps(), robot, calibration, scene, {1}, &error);
    EXPECT_TRUE(result) << error;
    return result ? *result : FrameEyeError{};
  }
};

TEST(EyeImageTruth, EyesAtTheCamerasSeeTheSceneWhereItIs) {
  TruthRig rig;
  const FrameEyeError e = rig.evaluate();
  ASSERT_GT(e.error_deg.size(), 10000u);
  EXPECT_LT(e.blind, e.evaluated / 100);
  EXPECT_NEAR(e.eye_camera_distance_m, 0.0, 1e-9);
  EXPECT_LT(quantile(e.error_deg, 1.0), 2e-3) << "only the float32 map's rounding";
}

TEST(EyeImageTruth, AnEyeOffTheCameraSeesTheSpheresDistortion) {
  TruthRig rig;
  // 5 cm to the right: the scene is nearer and farther than r = 1 m, so γ > 0 almost everywhere
  // but at most what eq. 4 gives for the farthest wall (the room is ≤ 6 m across).
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.translation().x() = 0.05;
  rig.frame.T_vr_hmd = rig.frame.T_vr_hmd * step;
  const FrameEyeError e = rig.evaluate();
  EXPECT_NEAR(e.eye_camera_distance_m, 0.05, 1e-9);
  EXPECT_GT(quantile(e.error_deg, 0.5), 0.1);
  EXPECT_LT(quantile(e.error_deg, 1.0), 4.0);
}

TEST(EyeImageTruth, AFrameStampedWithTheWrongPoseIsCaught) {
  TruthRig rig;
  // The joint buffer said the cameras were 5 mm lower than they were.
  for (auto& T : rig.frame.T_robot_cam_stamped) T.translation().z() -= 0.005;
  const FrameEyeError e = rig.evaluate();
  EXPECT_NEAR(e.stamp_position_error_m, 0.005, 1e-9);
  EXPECT_GT(quantile(e.error_deg, 0.99), 0.1);
}

TEST(EyeImageTruth, FilesWithBadRowsAreRefusedWithTheirLine) {
  const auto dir = std::filesystem::temp_directory_path() / "telesphere_truth_files_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream robot(dir / "robot.csv");
    robot << "sequence,capture_ns_left,capture_ns_right,mapping_set\n1,2,3,1\nx,2,3,1\n";
  }
  std::string error;
  EXPECT_FALSE(loadRobotTruth((dir / "robot.csv").string(), &error));
  EXPECT_NE(error.find("robot.csv:2:"), std::string::npos) << error;  // no pose columns
  EXPECT_FALSE(loadRobotTruth((dir / "missing.csv").string(), &error));
  EXPECT_NE(error.find("cannot read"), std::string::npos) << error;
  EXPECT_FALSE(loadXrTruthFrames(dir.string(), &error));  // no frames.csv
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace telesphere::truth
