// SPDX-License-Identifier: MIT
/// @brief Basalt calibration JSON import/export: Basalt's layout, lossless round trips for all
///        four models, errors naming the field.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "calib/basalt_calibration.h"
#include "tests/calib/calibration_samples.h"

namespace telesphere::test {
namespace {

// As Basalt writes it (TUM-VI-like stereo DS calibration, IMU fields abridged).
const char* const kBasalt = R"({
  "value0": {
    "T_imu_cam": [
      {"px": 0.04557, "py": -0.07116, "pz": -0.04468, "qx": -0.0092, "qy": 0.7124, "qz": -0.7016, "qw": -0.0117},
      {"px": -0.05557, "py": -0.06923, "pz": -0.04932, "qx": -0.0126, "qy": 0.6973, "qz": -0.7166, "qw": -0.0052}
    ],
    "intrinsics": [
      {"camera_type": "ds", "intrinsics": {"fx": 158.28, "fy": 158.27, "cx": 254.96, "cy": 256.88, "xi": -0.172, "alpha": 0.593}},
      {"camera_type": "ds", "intrinsics": {"fx": 157.91, "fy": 157.89, "cx": 252.56, "cy": 255.02, "xi": -0.171, "alpha": 0.592}}
    ],
    "resolution": [[512, 512], [512, 512]],
    "vignette": [],
    "cam_time_offset_ns": 0
  }
})";

TEST(BasaltCalibration, ReadsBasaltsLayout) {
  const auto r = calib::parseBasaltCalibration(kBasalt, "calibration.json");
  ASSERT_TRUE(r) << r.error().describe();
  ASSERT_EQ(r->cameras.size(), 2u);
  EXPECT_DOUBLE_EQ(r->cameras[1].camera.params()[5], 0.592);
  EXPECT_EQ(r->cameras[0].width, 512);
  // The baseline of the pair, whatever the IMU frame: about 10 cm.
  EXPECT_NEAR(r->T_cam_l_cam_r->translation().norm(), 0.1013, 1e-3);
}

TEST(BasaltCalibration, RoundTripIsLosslessForEveryModel) {
  for (const char* model : {"ds", "eucm", "kb4", "pinhole"}) {
    SCOPED_TRACE(model);
    const auto original = samplePair(model);
    const std::string text = calib::toBasaltCalibration(original);
    const auto back = calib::parseBasaltCalibration(text, "calibration.json");
    ASSERT_TRUE(back) << back.error().describe() << "\n" << text;
    expectSameCalibration(original, *back, /*with_hand_eye=*/false);
  }
  const auto j = nlohmann::json::parse(calib::toBasaltCalibration(samplePair("pinhole")));
  EXPECT_EQ(j["value0"]["intrinsics"][0]["camera_type"], "pinhole-radtan8");
  EXPECT_EQ(j["value0"]["intrinsics"][0]["intrinsics"]["k3"], 0.0);
}

TEST(BasaltCalibration, ErrorsNameTheField) {
  auto err = [](std::string text) {
    const auto r = calib::parseBasaltCalibration(text, "calibration.json");
    return r ? std::string("no error") : r.error().describe();
  };
  std::string fov = kBasalt;
  fov.replace(fov.find("\"camera_type\": \"ds\""), 19, "\"camera_type\": \"fov\"");
  EXPECT_EQ(err(fov), "calibration.json: value0.intrinsics[0].camera_type: \"fov\" is not supported "
                      "(ds, eucm, kb4, pinhole, pinhole-radtan8)");
  std::string bad_alpha = kBasalt;
  bad_alpha.replace(bad_alpha.find("\"alpha\": 0.592"), 14, "\"alpha\": -0.5");
  EXPECT_EQ(err(bad_alpha), "calibration.json: value0.intrinsics[1].intrinsics.alpha: alpha = -0.5 is outside [0, 1]");
  std::string missing = kBasalt;
  missing.replace(missing.find("\"fy\": 158.27, "), 14, "");
  EXPECT_EQ(err(missing), "calibration.json: value0.intrinsics[0].intrinsics.fy: missing");
  EXPECT_EQ(err("{\n\"value0\": {\n  \"intrinsics\": [,]\n}}").substr(0, 36), "calibration.json:3: JSON syntax: [js");
  const std::string radtan8 = R"({"value0": {"T_imu_cam": [{"px":0,"py":0,"pz":0,"qx":0,"qy":0,"qz":0,"qw":1}],
    "intrinsics": [{"camera_type": "pinhole-radtan8", "intrinsics": {"fx": 500, "fy": 500, "cx": 320,
    "cy": 240, "k1": 0.1, "k2": 0.01, "p1": 0, "p2": 0, "k3": 0.5, "k4": 0, "k5": 0, "k6": 0, "rpmax": 2}}],
    "resolution": [[640, 480]]}})";
  EXPECT_NE(err(radtan8).find("value0.intrinsics[0].intrinsics.k3: is 0.5"), std::string::npos);
}

}  // namespace
}  // namespace telesphere::test
