// SPDX-License-Identifier: MIT
/// @brief Reading and writing our system calibration YAML.
#include "calib/system_calibration_yaml.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>

#include "calib/yaml_reader.h"

namespace telesphere::calib {
namespace {

using detail::YamlReader;

CameraCalibration readCameraEntry(const YamlReader& in, const YAML::Node& node, const std::string& field) {
  if (!node.IsMap()) in.fail(node, field, "expected a map");
  in.onlyKeys(node, field, {"label", "model", "resolution", "intrinsics"});
  const std::string label = in.text(in.require(node, "label", field + ".label"), field + ".label");
  const YAML::Node model_node = in.require(node, "model", field + ".model");
  const std::string model = in.text(model_node, field + ".model");
  const auto names = GenericCamera::paramNames(model);
  if (names.empty()) in.fail(model_node, field + ".model", "unknown camera model \"" + model + "\" (known: ds, eucm, kb4, pinhole)");
  const auto res = in.numbers(in.require(node, "resolution", field + ".resolution"), field + ".resolution", 2);
  const YAML::Node intr = in.require(node, "intrinsics", field + ".intrinsics");
  if (!intr.IsMap()) in.fail(intr, field + ".intrinsics", "expected a map of named parameters");
  Eigen::VectorXd params(static_cast<Eigen::Index>(names.size()));
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string name(names[i]);
    params[static_cast<Eigen::Index>(i)] =
        in.number(in.require(intr, name.c_str(), field + ".intrinsics." + name), field + ".intrinsics." + name);
  }
  for (const auto& kv : intr) {
    const std::string key = kv.first.as<std::string>();
    bool known = false;
    for (auto n : names) known = known || key == n;
    if (!known) in.fail(kv.first, field + ".intrinsics." + key, "not a parameter of model \"" + model + "\"");
  }
  std::string error;
  auto camera = GenericCamera::create(model, params, &error);
  if (!camera) {
    // The model's message starts with the parameter's name: point at that parameter's line.
    const std::string name = error.substr(0, error.find(' '));
    const YAML::Node bad = intr[name];
    in.fail(bad.IsDefined() ? bad : intr, field + ".intrinsics" + (bad.IsDefined() ? "." + name : ""), error);
  }
  const double w = res[0], h = res[1];
  if (w != std::floor(w) || h != std::floor(h)) in.fail(node["resolution"], field + ".resolution", "width and height must be whole pixels");
  return CameraCalibration{label, *camera, static_cast<int>(w), static_cast<int>(h)};
}

SystemCalibration readSystem(const YamlReader& in, const YAML::Node& root) {
  if (!root.IsMap()) in.fail(root, "", "expected a map with version, cameras and extrinsics");
  in.onlyKeys(root, "", {"version", "cameras", "extrinsics"});
  const YAML::Node version_node = in.require(root, "version", "version");
  const int version = in.integer(version_node, "version");
  if (version != kSystemCalibrationVersion)
    in.fail(version_node, "version",
            std::to_string(version) + " is not a version this build reads (it reads " +
                std::to_string(kSystemCalibrationVersion) + ")");
  SystemCalibration calib;
  const YAML::Node cams = in.require(root, "cameras", "cameras");
  if (!cams.IsSequence()) in.fail(cams, "cameras", "expected a list of cameras");
  for (std::size_t i = 0; i < cams.size(); ++i)
    calib.cameras.push_back(readCameraEntry(in, cams[i], "cameras[" + std::to_string(i) + "]"));
  YAML::Node ext = root["extrinsics"];
  if (ext.IsDefined() && !ext.IsNull()) {
    in.onlyKeys(ext, "extrinsics", {"T_cam_l_cam_r", "T_flange_cam_l", "T_robot_mount", "T_wrist_marker"});
    const auto opt = [&](const char* key, std::optional<Eigen::Isometry3d>& out) {
      if (ext[key].IsDefined() && !ext[key].IsNull())
        out = in.transform(ext[key], std::string("extrinsics.") + key);
    };
    opt("T_cam_l_cam_r", calib.T_cam_l_cam_r);
    opt("T_flange_cam_l", calib.T_flange_cam_l);
    opt("T_robot_mount", calib.T_robot_mount);
    opt("T_wrist_marker", calib.T_wrist_marker);
  }
  if (auto problem = calib.inconsistency())
    throw FileErrorException(
        FileError{in.path(), in.lineOf(root, problem->first), problem->first, problem->second});
  return calib;
}

void emitTransform(YAML::Emitter& out, const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  out << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "translation" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << T.translation().x() << T.translation().y() << T.translation().z() << YAML::EndSeq;
  out << YAML::Key << "rotation_xyzw" << YAML::Value << YAML::Flow << YAML::BeginSeq << q.x()
      << q.y() << q.z() << q.w() << YAML::EndSeq;
  out << YAML::EndMap;
}

}  // namespace

FileResult<SystemCalibration> parseSystemCalibrationYaml(const std::string& text,
                                                         const std::string& path) {
  return detail::readYamlCalibration(text, path, readSystem);
}

std::string toSystemCalibrationYaml(const SystemCalibration& calib) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::Comment("telesphere system calibration (DESIGN.md §2); T_a_b maps points from b into a, metres");
  out << YAML::BeginMap;
  out << YAML::Key << "version" << YAML::Value << kSystemCalibrationVersion;
  out << YAML::Key << "cameras" << YAML::Value << YAML::BeginSeq;
  for (const auto& cam : calib.cameras) {
    out << YAML::BeginMap;
    out << YAML::Key << "label" << YAML::Value << cam.label;
    out << YAML::Key << "model" << YAML::Value << std::string(cam.camera.modelName());
    out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << YAML::BeginSeq << cam.width
        << cam.height << YAML::EndSeq;
    out << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << YAML::BeginMap;
    const auto names = GenericCamera::paramNames(cam.camera.modelName());
    const Eigen::VectorXd p = cam.camera.params();
    for (std::size_t i = 0; i < names.size(); ++i)
      out << YAML::Key << std::string(names[i]) << YAML::Value << p[static_cast<Eigen::Index>(i)];
    out << YAML::EndMap << YAML::EndMap;
  }
  out << YAML::EndSeq;
  const std::pair<const char*, const std::optional<Eigen::Isometry3d>*> transforms[] = {
      {"T_cam_l_cam_r", &calib.T_cam_l_cam_r},
      {"T_flange_cam_l", &calib.T_flange_cam_l},
      {"T_robot_mount", &calib.T_robot_mount},
      {"T_wrist_marker", &calib.T_wrist_marker}};
  out << YAML::Key << "extrinsics" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, T] : transforms) {
    if (!*T) continue;
    out << YAML::Key << name << YAML::Value;
    emitTransform(out, **T);
  }
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace telesphere::calib
