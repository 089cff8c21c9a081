// SPDX-License-Identifier: MIT
/// @brief HeadTrajectory: CSV with header and comments, line-numbered errors for every kind of
///        bad line, interpolation (lerp + slerp) between samples, holding and looping outside.
#include <gtest/gtest.h>

#include <cmath>

#include "xr/frame_loop/head_trajectory.h"

namespace telesphere::xr {
namespace {

TEST(HeadTrajectory, ParsesAndInterpolates) {
  const std::string csv =
      "t,px,py,pz,qx,qy,qz,qw\n"
      "# standing still, then turning 90° about y while stepping 1 m\n"
      "0, 0,1.6,0, 0,0,0,1\n"
      "1.0, 1,1.6,0, 0,0.70710678118654752,0,0.70710678118654752\n";
  std::string error;
  const auto trajectory = frame_loop::HeadTrajectory::parse(csv, "traj.csv", &error);
  ASSERT_TRUE(trajectory) << error;
  EXPECT_EQ(trajectory->samples().size(), 2u);
  EXPECT_DOUBLE_EQ(trajectory->durationS(), 1.0);
  const Eigen::Isometry3d mid = trajectory->sample(0.5);
  EXPECT_NEAR(mid.translation().x(), 0.5, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(mid.rotation()).angle(), M_PI / 4.0, 1e-9);  // slerp: half the angle
  EXPECT_NEAR(trajectory->sample(-3.0).translation().x(), 0.0, 1e-12);      // holds the first
  EXPECT_NEAR(trajectory->sample(7.0).translation().x(), 1.0, 1e-12);       // holds the last
  EXPECT_NEAR(trajectory->sample(2.25, true).translation().x(), 0.25, 1e-12);  // loops
  EXPECT_NEAR(trajectory->sample(-0.25, true).translation().x(), 0.75, 1e-12);
}

TEST(HeadTrajectory, NormalisesQuaternions) {
  std::string error;
  const auto trajectory = frame_loop::HeadTrajectory::parse("0 0 0 0 0 0 0 2\n", "q", &error);
  ASSERT_TRUE(trajectory) << error;
  EXPECT_TRUE(trajectory->sample(0).rotation().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST(HeadTrajectory, BadLinesAreReportedWithTheirLineNumber) {
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {"0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 1\n", "f.csv:2: 7 values"},
      {"0 0 0 0 0 0 0 1 9\n", "f.csv:1: more than 8"},
      {"0 0 0 x 0 0 0 1\n", "f.csv:1: 'x' is not a finite number"},
      {"0 0 0 nan 0 0 0 1\n", "not a finite number"},
      {"0 0 0 0 0 0 0 0\n", "f.csv:1: quaternion has zero length"},
      {"1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", "f.csv:2: time 1.000000 s does not increase"},
      {"# nothing\n\n", "f.csv: no poses"},
  };
  for (const Case& c : cases) {
    std::string error;
    EXPECT_FALSE(frame_loop::HeadTrajectory::parse(c.text, "f.csv", &error)) << c.text;
    EXPECT_NE(error.find(c.expected), std::string::npos) << error << " vs " << c.expected;
  }
  std::string error;
  EXPECT_FALSE(frame_loop::HeadTrajectory::load("/nonexistent/traj.csv", &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos);
}

TEST(HeadTrajectory, DemoMotionStaysInItsRanges) {
  const frame_loop::HeadTrajectory demo = frame_loop::HeadTrajectory::demo(8.0);
  EXPECT_NEAR(demo.durationS(), 8.0, 1e-12);
  for (double t = 0; t <= 8.0; t += 0.01) {
    const Eigen::Isometry3d T = demo.sample(t);
    EXPECT_NEAR(T.translation().y(), 1.6, 1e-12);
    EXPECT_LE(std::abs(T.translation().x()), 0.05 + 1e-12);
    EXPECT_LE(Eigen::AngleAxisd(T.rotation()).angle(), (31.7 * M_PI / 180.0));
  }
}

}  // namespace
}  // namespace telesphere::xr
