// SPDX-License-Identifier: MIT
/// @brief Our calibration YAML: exact round trips, and errors that name the field and the line
///        for malformed or inconsistent files; the format-detecting loader and atomic saving.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "calib/calibration_file.h"
#include "calib/system_calibration_yaml.h"
#include "tests/calib/calibration_samples.h"

namespace telesphere::test {
namespace {

using calib::parseSystemCalibrationYaml;
using calib::toSystemCalibrationYaml;

const char* const kGood = R"(version: 1
cameras:
  - label: cam_l
    model: ds
    resolution: [3840, 2160]
    intrinsics: {fx: 930, fy: 931, cx: 1919.5, cy: 1079.5, xi: -0.18, alpha: 0.59}
  - label: cam_r
    model: ds
    resolution: [3840, 2160]
    intrinsics: {fx: 929, fy: 930, cx: 1920.5, cy: 1078.5, xi: -0.17, alpha: 0.6}
extrinsics:
  T_cam_l_cam_r: {translation: [0.064, 0, 0], rotation_xyzw: [0, 0, 0, 1]}
)";

/// The error of parsing `text`, as "line: field: message".
std::string errorOf(const std::string& text) {
  const auto r = parseSystemCalibrationYaml(text, "calib.yaml");
  if (r) return "no error";
  const auto& e = r.error();
  return std::to_string(e.line) + ": " + (e.field.empty() ? "" : e.field + ": ") + e.message;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SystemCalibrationYaml, ReadsTheDocumentedFormat) {
  const auto r = parseSystemCalibrationYaml(kGood, "calib.yaml");
  ASSERT_TRUE(r) << r.error().describe();
  ASSERT_EQ(r->cameras.size(), 2u);
  EXPECT_EQ(r->cameras[1].camera.modelName(), "ds");
  EXPECT_DOUBLE_EQ(r->cameras[1].camera.params()[5], 0.6);
  EXPECT_EQ(r->cameras[0].width, 3840);
  EXPECT_DOUBLE_EQ(r->T_cam_l_cam_r->translation().x(), 0.064);
  EXPECT_FALSE(r->T_flange_cam_l);
}

TEST(SystemCalibrationYaml, RoundTripIsExactForEveryModel) {
  for (const char* model : {"ds", "eucm", "kb4", "pinhole"}) {
    SCOPED_TRACE(model);
    const auto original = samplePair(model);
    const std::string text = toSystemCalibrationYaml(original);
    const auto back = parseSystemCalibrationYaml(text, "x.yaml");
    ASSERT_TRUE(back) << back.error().describe() << "\n" << text;
    expectSameCalibration(original, *back);
  }
}

TEST(SystemCalibrationYaml, ErrorsNameTheFieldAndTheLine) {
  EXPECT_EQ(errorOf(replaced(kGood, "alpha: 0.6}", "alpha: 1.3}")),
            "10: cameras[1].intrinsics.alpha: alpha = 1.3 is outside [0, 1]");
  EXPECT_EQ(errorOf(replaced(kGood, "xi: -0.17, ", "")), "10: cameras[1].intrinsics.xi: missing");
  EXPECT_EQ(errorOf(replaced(kGood, "xi: -0.17", "xj: -0.17")),
            "10: cameras[1].intrinsics.xi: missing");
  EXPECT_EQ(errorOf(replaced(kGood, "alpha: 0.6}", "alpha: 0.6, beta: 1}")),
            "10: cameras[1].intrinsics.beta: not a parameter of model \"ds\"");
  EXPECT_EQ(errorOf(replaced(kGood, "fy: 931,", "fy: abc,")),
            "6: cameras[0].intrinsics.fy: \"abc\" is not a number");
  EXPECT_EQ(errorOf(replaced(kGood, "model: ds\n    resolution: [3840, 2160]\n    intrinsics: {fx: 929",
                             "model: omni\n    resolution: [3840, 2160]\n    intrinsics: {fx: 929")),
            "8: cameras[1].model: unknown camera model \"omni\" (known: ds, eucm, kb4, pinhole)");
  EXPECT_EQ(errorOf(replaced(kGood, "version: 1", "version: 7")),
            "1: version: 7 is not a version this build reads (it reads 1)");
  EXPECT_EQ(errorOf(replaced(kGood, "version: 1\n", "")), "1: version: missing");
  EXPECT_EQ(errorOf(replaced(kGood, "resolution: [3840, 2160]", "resolution: [3840]")),
            "5: cameras[0].resolution: expected 2 numbers, got 1");
  EXPECT_EQ(errorOf(replaced(kGood, "  - label: cam_l", "  - lable: cam_l")),
            "3: cameras[0].lable: unknown field (expected one of: label, model, resolution, intrinsics)");
  EXPECT_EQ(errorOf(replaced(kGood, "rotation_xyzw: [0, 0, 0, 1]", "rotation_xyzw: [0, 0, 0, 1.2]")),
            "12: extrinsics.T_cam_l_cam_r.rotation_xyzw: has norm 1.2, not a unit quaternion");
  EXPECT_EQ(errorOf(replaced(kGood, "intrinsics: {fx: 930", "intrinsics: [930")).substr(0, 30),
            "6: YAML syntax: illegal flow e");
}

TEST(SystemCalibrationYaml, InconsistentContentIsRefused) {
  EXPECT_EQ(errorOf(replaced(kGood, "  T_cam_l_cam_r: {translation: [0.064, 0, 0], rotation_xyzw: [0, 0, 0, 1]}\n", "")),
            "11: extrinsics.T_cam_l_cam_r: missing: a stereo pair needs it");
  EXPECT_EQ(errorOf(replaced(kGood, "label: cam_r", "label: cam_l")),
            "7: cameras[1].label: is \"cam_l\", expected \"cam_r\"");
  EXPECT_EQ(errorOf(replaced(kGood, "cx: 1920.5", "cx: 5000")),
            "10: cameras[1].intrinsics: principal point (5000, 1078.5) lies outside the 3840x2160 image");
  EXPECT_EQ(errorOf(replaced(kGood, "resolution: [3840, 2160]", "resolution: [0, 2160]")),
            "5: cameras[0].resolution: 0x2160 is not an image size in (0, 32768]");
}

TEST(CalibrationFile, SavesAtomicallyAndLoadsEveryFormat) {
  const auto dir = std::filesystem::temp_directory_path() / "telesphere_test_calibration_file";
  std::filesystem::create_directories(dir);
  const auto original = samplePair("ds");
  for (auto format : {calib::CalibrationFormat::kTelesphere, calib::CalibrationFormat::kKalibr,
                      calib::CalibrationFormat::kBasalt}) {
    const std::string path = (dir / ("calib." + std::string(calib::formatName(format)))).string();
    ASSERT_FALSE(calib::saveCalibrationFile(original, path, format));
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(calib::detectCalibrationFormat(text), format);
    const auto back = calib::loadCalibrationFile(path);
    ASSERT_TRUE(back) << back.error().describe();
    expectSameCalibration(original, *back, format == calib::CalibrationFormat::kTelesphere);
  }
  const auto missing = calib::loadCalibrationFile((dir / "nope.yaml").string());
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().describe().find("nope.yaml: cannot open: No such file"), std::string::npos);
  auto bad = original;
  bad.T_cam_l_cam_r.reset();
  const auto refused = calib::saveCalibrationFile(bad, (dir / "bad.yaml").string(),
                                                  calib::CalibrationFormat::kTelesphere);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->field, "extrinsics.T_cam_l_cam_r");
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.yaml"));
  const auto unknown = calib::parseCalibration("just: text\n", "x.yaml");
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().message.find("not a calibration file we know"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace telesphere::test
