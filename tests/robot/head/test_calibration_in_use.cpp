// SPDX-License-Identifier: MIT
/// @brief CalibrationInUse (issue #15, applying a calibration live): generations, the merge of a
///        partial result, refusals with their reasons (unparsable, one camera, another aspect
///        ratio, no hand-eye), revert through the kept history and past its end, the link's
///        requests, and camera poses at capture times through the calibration in use (exactly
///        FK · T_flange_cam, the fallback pose before any joint state).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>

#include "calib/calibration_file.h"
#include "calib/system_calibration_yaml.h"
#include "robot/head/calibration_in_use.h"
#include "robot/clock/sim_clock.h"

namespace telesphere::robot {
namespace {

calib::SystemCalibration simCalibration() {
  auto loaded = calib::loadCalibrationFile(std::string(TELESPHERE_SOURCE_DIR) + "/calib/data/sim_calibration.yaml");
  EXPECT_TRUE(loaded) << loaded.error().describe();
  return *loaded;
}

Eigen::Isometry3d shifted(const Eigen::Isometry3d& T, double dx_m, double angle_deg) {
  Eigen::Isometry3d out = T;
  out.translation().x() += dx_m;
  out.linear() = out.linear() * Eigen::AngleAxisd(angle_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return out;
}

TEST(CalibrationInUse, StartsAtGenerationOneAndRefusesAnUnusableStart) {
  clock::SimClock clock(1'000);
  const auto start = simCalibration();
  head::CalibrationInUse in_use(start, "--calib sim", clock);
  EXPECT_EQ(in_use.current()->generation, 1u);
  EXPECT_EQ(in_use.current()->source, "--calib sim");
  EXPECT_EQ(in_use.previousCount(), 0u);
  EXPECT_TRUE(in_use.current()->geometry.T_flange_cam_l.isApprox(*start.T_flange_cam_l));

  calib::SystemCalibration no_hand_eye = start;
  no_hand_eye.T_flange_cam_l.reset();
  EXPECT_NE(head::CalibrationInUse::unusable(no_hand_eye).value_or("").find("T_flange_cam_l"), std::string::npos);
  EXPECT_THROW(head::CalibrationInUse(no_hand_eye, "x", clock), std::invalid_argument);
}

TEST(CalibrationInUse, AppliesMergesAndRevertsThroughTheHistory) {
  clock::SimClock clock(1'000);
  const auto start = simCalibration();
  head::CalibrationInUse in_use(start, "start", clock);
  std::string error;

  // A hand-eye result only: the cameras stay as they are.
  calib::SystemCalibration hand_eye = start;
  hand_eye.T_flange_cam_l = shifted(*start.T_flange_cam_l, 0.012, 1.5);
  clock.advance(5'000'000);
  ASSERT_TRUE(in_use.apply(hand_eye, "hand-eye", &error)) << error;
  EXPECT_EQ(in_use.current()->generation, 2u);
  EXPECT_EQ(in_use.current()->applied_ns, 5'001'000);
  EXPECT_TRUE(in_use.current()->geometry.T_flange_cam_l.isApprox(*hand_eye.T_flange_cam_l));

  // An intrinsics result without T_flange_cam_l keeps the one in use (the hand-eye just applied).
  calib::SystemCalibration intrinsics = start;
  intrinsics.T_flange_cam_l.reset();
  Eigen::VectorXd p = intrinsics.cameras[0].camera.params();
  p[0] *= 1.01;
  intrinsics.cameras[0].camera = *calib::GenericCamera::create(intrinsics.cameras[0].camera.modelName(), p);
  ASSERT_TRUE(in_use.apply(intrinsics, "intrinsics", &error)) << error;
  EXPECT_EQ(in_use.current()->generation, 3u);
  EXPECT_TRUE(in_use.current()->calibration.T_flange_cam_l->isApprox(*hand_eye.T_flange_cam_l));
  EXPECT_DOUBLE_EQ(in_use.current()->calibration.cameras[0].camera.params()[0], p[0]);
  EXPECT_EQ(in_use.previousCount(), 2u);

  // Revert twice: back through the intrinsics to the start, each a new generation.
  ASSERT_TRUE(in_use.revert(&error)) << error;
  EXPECT_EQ(in_use.current()->generation, 4u);
  EXPECT_NE(in_use.current()->source.find("reverted to generation 2"), std::string::npos) << in_use.current()->source;
  EXPECT_DOUBLE_EQ(in_use.current()->calibration.cameras[0].camera.params()[0], start.cameras[0].camera.params()[0]);
  ASSERT_TRUE(in_use.revert(&error)) << error;
  EXPECT_EQ(in_use.current()->generation, 5u);
  EXPECT_TRUE(in_use.current()->geometry.T_flange_cam_l.isApprox(*start.T_flange_cam_l));
  EXPECT_FALSE(in_use.revert(&error));
  EXPECT_NE(error.find("no earlier calibration"), std::string::npos) << error;
  EXPECT_EQ(in_use.current()->generation, 5u);
}

// Issue #30: a calibration applied live is saved where the robot was told (--calib-save), so a
// restart with --calib that file keeps it; without a path, or when it cannot be written, the
// link's view says so (the console warns).
TEST(CalibrationInUse, SavesEveryAppliedCalibrationWhereItWasToldAndSaysWhenItCannot) {
  clock::SimClock clock(1'000);
  const auto start = simCalibration();
  head::CalibrationInUse in_use(start, "start", clock);
  std::string error;
  calib::SystemCalibration hand_eye = start;
  hand_eye.T_flange_cam_l = shifted(*start.T_flange_cam_l, 0.012, 1.5);
  ASSERT_TRUE(in_use.apply(hand_eye, "hand-eye", &error)) << error;
  link::proto::CalibrationInUse view;
  in_use.fill(&view);
  EXPECT_EQ(view.saved_to(), "");  // no path: not saved

  const std::string path = ::testing::TempDir() + "/telesphere-calib-save-" + std::to_string(getpid()) + ".yaml";
  in_use.setSavePath(path);
  hand_eye.T_flange_cam_l = shifted(*start.T_flange_cam_l, 0.020, -2.0);
  ASSERT_TRUE(in_use.apply(hand_eye, "hand-eye again", &error)) << error;
  in_use.fill(&view);
  EXPECT_EQ(view.saved_to(), path);
  EXPECT_EQ(view.save_error(), "");
  const auto saved = calib::loadCalibrationFile(path);
  ASSERT_TRUE(saved) << saved.error().describe();
  EXPECT_TRUE(saved->T_flange_cam_l->isApprox(*hand_eye.T_flange_cam_l, 1e-9));
  // A revert is saved too.
  ASSERT_TRUE(in_use.revert(&error)) << error;
  const auto reverted = calib::loadCalibrationFile(path);
  ASSERT_TRUE(reverted);
  EXPECT_FALSE(reverted->T_flange_cam_l->isApprox(*hand_eye.T_flange_cam_l, 1e-6));
  std::remove(path.c_str());

  in_use.setSavePath("/nonexistent-folder-telesphere/calib.yaml");
  ASSERT_TRUE(in_use.apply(hand_eye, "unsaveable", &error)) << error;  // in use all the same
  in_use.fill(&view);
  EXPECT_EQ(view.saved_to(), "");
  EXPECT_NE(view.save_error().find("cannot write"), std::string::npos) << view.save_error();
}

TEST(CalibrationInUse, RefusesWhatDoesNotFitTheseCamerasAndKeepsOnlyTheNewestHistory) {
  clock::SimClock clock;
  const auto start = simCalibration();
  head::CalibrationInUse in_use(start, "start", clock);
  std::string error;

  calib::SystemCalibration square = start;  // 16:9 cameras calibrated as 1:1
  square.cameras[1].height = square.cameras[1].width;
  square.cameras[1].camera = *calib::GenericCamera::create(
      start.cameras[1].camera.modelName(), [&] {
        Eigen::VectorXd p = start.cameras[1].camera.params();
        p[3] = square.cameras[1].height / 2.0;
        return p;
      }());
  EXPECT_FALSE(in_use.apply(square, "square", &error));
  EXPECT_NE(error.find("aspect ratio"), std::string::npos) << error;

  calib::SystemCalibration one = start;
  one.cameras.pop_back();
  one.T_cam_l_cam_r.reset();
  EXPECT_FALSE(in_use.apply(one, "one camera", &error));
  EXPECT_NE(error.find("two cameras"), std::string::npos) << error;
  EXPECT_EQ(in_use.current()->generation, 1u) << "a refused apply changes nothing";

  for (int i = 0; i < int(head::CalibrationInUse::kMaxPrevious) + 5; ++i) {
    calib::SystemCalibration c = start;
    c.T_flange_cam_l = shifted(*start.T_flange_cam_l, 0.001 * (i + 1), 0);
    ASSERT_TRUE(in_use.apply(c, "step " + std::to_string(i), &error)) << error;
  }
  EXPECT_EQ(in_use.previousCount(), head::CalibrationInUse::kMaxPrevious);
  std::size_t reverts = 0;
  while (in_use.revert(&error)) ++reverts;
  EXPECT_EQ(reverts, head::CalibrationInUse::kMaxPrevious);
  EXPECT_NE(in_use.current()->source.find("step 4"), std::string::npos) << "the oldest kept (start and steps 0–3 dropped): " << in_use.current()->source;
}

TEST(CalibrationInUse, AnswersTheLinksRequests) {
  clock::SimClock clock;
  const auto start = simCalibration();
  head::CalibrationInUse in_use(start, "start", clock);

  link::proto::ControlRequest get;
  get.set_id(7);
  get.set_get_calibration(true);
  auto reply = in_use.handleControl(get);
  EXPECT_TRUE(reply.ok());
  EXPECT_EQ(reply.id(), 7u);
  EXPECT_EQ(reply.calibration().generation(), 1u);
  const auto round_trip = calib::parseCalibration(reply.calibration().yaml(), "reply");
  ASSERT_TRUE(round_trip) << round_trip.error().describe();
  EXPECT_TRUE(round_trip->T_flange_cam_l->isApprox(*start.T_flange_cam_l, 1e-15));
  EXPECT_EQ(round_trip->cameras[0].camera.params(), start.cameras[0].camera.params()) << "17 digits: exact";

  link::proto::ControlRequest garbage;
  garbage.mutable_apply_calibration()->set_text("version: 1\ncameras: [oops");
  reply = in_use.handleControl(garbage);
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("not applied"), std::string::npos) << reply.error();
  EXPECT_EQ(reply.calibration().generation(), 1u) << "the reply says what is still in use";

  calib::SystemCalibration moved = start;
  moved.T_flange_cam_l = shifted(*start.T_flange_cam_l, 0.02, 0);
  link::proto::ControlRequest apply;
  apply.mutable_apply_calibration()->set_text(calib::toSystemCalibrationYaml(moved));
  apply.mutable_apply_calibration()->set_source("hand-eye wizard");
  reply = in_use.handleControl(apply);
  ASSERT_TRUE(reply.ok()) << reply.error();
  EXPECT_EQ(reply.calibration().generation(), 2u);
  EXPECT_EQ(reply.calibration().source(), "hand-eye wizard");
  EXPECT_EQ(reply.calibration().previous(), 1u);
  EXPECT_EQ(reply.calibration().previous_source(), "start");

  link::proto::ControlRequest revert;
  revert.set_revert_calibration(true);
  reply = in_use.handleControl(revert);
  ASSERT_TRUE(reply.ok()) << reply.error();
  EXPECT_EQ(reply.calibration().generation(), 3u);
  reply = in_use.handleControl(revert);
  EXPECT_FALSE(reply.ok());
}

TEST(CalibrationInUse, CameraPosesComeFromTheJointsThroughTheCalibrationInUse) {
  clock::SimClock clock;
  const auto start = simCalibration();
  head::CalibrationInUse in_use(start, "start", clock);
  head::JointStateBuffer joints{head::HeadGeometry{}};
  arm::JointVector q0;
  q0 << 0.1, -0.4, -0.9, 0.05, -0.5, 0.2;
  arm::JointVector q1 = q0 + arm::JointVector::Constant(0.02);
  joints.push({1'000'000'000, q0});
  joints.push({1'010'000'000, q1});
  const arm::Xarm6Kinematics kinematics;

  // Before any joint state: the fallback configuration, flagged unmeasured.
  head::StereoCameraPoses poses = in_use.posesAt(joints, q0, 10, 10);
  EXPECT_FALSE(poses.measured_l);
  EXPECT_FALSE(poses.measured_r);
  EXPECT_TRUE(poses.T_robot_cam_l.isApprox(kinematics.forward(q0) * *start.T_flange_cam_l, 1e-12));

  const auto check = [&](const calib::SystemCalibration& c, std::uint64_t generation) {
    const head::StereoCameraPoses p = in_use.posesAt(joints, q0, 1'005'000'000, 1'010'000'000);
    EXPECT_TRUE(p.measured_l && p.measured_r);
    EXPECT_EQ(p.calibration_generation, generation);
    const arm::JointVector q_mid = 0.5 * (q0 + q1);
    EXPECT_TRUE(p.T_robot_cam_l.isApprox(kinematics.forward(q_mid) * *c.T_flange_cam_l, 1e-12));
    EXPECT_TRUE(p.T_robot_cam_r.isApprox(kinematics.forward(q1) * *c.T_flange_cam_l * *c.T_cam_l_cam_r, 1e-12));
  };
  check(start, 1);
  calib::SystemCalibration moved = start;
  moved.T_flange_cam_l = shifted(*start.T_flange_cam_l, -0.03, 4.0);
  moved.T_cam_l_cam_r = shifted(*start.T_cam_l_cam_r, 0.002, 0.3);
  std::string error;
  ASSERT_TRUE(in_use.apply(moved, "moved", &error)) << error;
  check(moved, 2);
}

}  // namespace
}  // namespace telesphere::robot
