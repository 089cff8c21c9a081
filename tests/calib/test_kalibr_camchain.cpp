// SPDX-License-Identifier: MIT
/// @brief kalibr camchain import/export: the published field layout, lossless round trips for
///        ds, eucm, pinhole-radtan and pinhole-equidistant (kb4), clear errors otherwise.
#include <gtest/gtest.h>

#include "calib/kalibr_camchain.h"
#include "tests/calib/calibration_samples.h"

namespace telesphere::test {
namespace {

// As kalibr writes it (values from a public 1440×1080 DS calibration, abridged).
const char* const kCamchain = R"(cam0:
  cam_overlaps: [1]
  camera_model: ds
  distortion_coeffs: []
  distortion_model: none
  intrinsics: [-0.19963086018860057, 0.5924590037637837, 317.552559595926, 316.1745713358917,
    724.8551471226007, 546.5708052642561]
  resolution: [1440, 1080]
  rostopic: /fisheye_left/image_raw
cam1:
  T_cn_cnm1:
  - [0.9994397899015358, 0.01583231520610129, 0.029486338477008038, -0.1982100882850154]
  - [-0.014069141538300084, 0.9981545353408604, -0.05907269110882186, -0.003226884424352984]
  - [-0.03036717994712894, 0.05862475052124023, 0.9978181061738522, 0.0003909535695235701]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [0]
  camera_model: ds
  distortion_coeffs: []
  distortion_model: none
  intrinsics: [-0.2, 0.59, 318.0, 316.0, 720.0, 540.0]
  resolution: [1440, 1080]
  rostopic: /fisheye_right/image_raw
)";

TEST(KalibrCamchain, ReadsKalibrsLayout) {
  const auto r = calib::parseKalibrCamchain(kCamchain, "camchain.yaml");
  ASSERT_TRUE(r) << r.error().describe();
  ASSERT_EQ(r->cameras.size(), 2u);
  const Eigen::VectorXd p = r->cameras[0].camera.params();
  EXPECT_EQ(r->cameras[0].camera.modelName(), "ds");
  EXPECT_DOUBLE_EQ(p[0], 317.552559595926);          // fx: kalibr's third value
  EXPECT_DOUBLE_EQ(p[4], -0.19963086018860057);       // xi: kalibr's first value
  EXPECT_DOUBLE_EQ(p[5], 0.5924590037637837);         // alpha
  // T_cn_cnm1 maps cam0 (left) into cam1 (right): T_cam_l_cam_r is its inverse.
  EXPECT_NEAR((r->T_cam_l_cam_r->inverse().translation() -
               Eigen::Vector3d(-0.1982100882850154, -0.003226884424352984, 0.0003909535695235701))
                  .norm(),
              0.0, 1e-15);
}

TEST(KalibrCamchain, RoundTripIsLosslessForEveryModelWeShare) {
  for (const char* model : {"ds", "eucm", "kb4", "pinhole"}) {
    SCOPED_TRACE(model);
    const auto original = samplePair(model);
    const std::string text = calib::toKalibrCamchain(original);
    const auto back = calib::parseKalibrCamchain(text, "camchain.yaml");
    ASSERT_TRUE(back) << back.error().describe() << "\n" << text;
    expectSameCalibration(original, *back, /*with_hand_eye=*/false);
  }
  // The model names kalibr expects.
  EXPECT_NE(calib::toKalibrCamchain(samplePair("kb4")).find("distortion_model: equidistant"), std::string::npos);
  EXPECT_NE(calib::toKalibrCamchain(samplePair("pinhole")).find("distortion_model: radtan"), std::string::npos);
}

TEST(KalibrCamchain, ErrorsNameTheField) {
  auto err = [](std::string text) {
    const auto r = calib::parseKalibrCamchain(text, "camchain.yaml");
    return r ? std::string("no error") : r.error().describe();
  };
  std::string omni = kCamchain;
  omni.replace(omni.find("camera_model: ds"), 16, "camera_model: omni");
  EXPECT_EQ(err(omni), "camchain.yaml:3: cam0.camera_model: camera_model omni is not supported (ds, eucm, pinhole)");
  std::string short_intr = kCamchain;
  short_intr.replace(short_intr.find("-0.2, 0.59, "), 12, "");
  EXPECT_EQ(err(short_intr), "camchain.yaml:20: cam1.intrinsics: camera_model ds takes 6 intrinsics, got 4");
  std::string bad_rotation = kCamchain;
  bad_rotation.replace(bad_rotation.find("0.9994397899015358"), 18, "1.9994397899015358");
  EXPECT_NE(err(bad_rotation).find("cam1.T_cn_cnm1: rotation part is not orthonormal"), std::string::npos);
  EXPECT_EQ(err(std::string(kCamchain) + "cam2:\n  camera_model: ds\n"),
            "camchain.yaml:23: cam2: telesphere takes one camera or a stereo pair (cam0, cam1)");
  std::string bad_alpha = kCamchain;
  bad_alpha.replace(bad_alpha.find("0.5924590037637837"), 18, "1.5924590037637837");
  EXPECT_EQ(err(bad_alpha).substr(0, 60), "camchain.yaml:6: cam0.intrinsics: alpha = 1.5924590037637838");
}

}  // namespace
}  // namespace telesphere::test
