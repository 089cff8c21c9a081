// SPDX-License-Identifier: MIT
/// @brief kalibr camchain.yaml import and export.
#include "calib/kalibr_camchain.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

#include "calib/yaml_reader.h"

namespace telesphere::calib {
namespace {

using detail::YamlReader;

CameraCalibration readKalibrCamera(const YamlReader& in, const YAML::Node& node, const std::string& cam,
                             const char* label) {
  if (!node.IsMap()) in.fail(node, cam, "expected a map");
  const YAML::Node model_node = in.require(node, "camera_model", cam + ".camera_model");
  const std::string model = in.text(model_node, cam + ".camera_model");
  const YAML::Node intr_node = in.require(node, "intrinsics", cam + ".intrinsics");
  const auto intr = in.numbers(intr_node, cam + ".intrinsics");
  std::string distortion = "none";
  if (node["distortion_model"].IsDefined())
    distortion = in.text(node["distortion_model"], cam + ".distortion_model");
  std::vector<double> coeffs;
  if (node["distortion_coeffs"].IsDefined())
    coeffs = in.numbers(node["distortion_coeffs"], cam + ".distortion_coeffs");
  const auto expect = [&](std::size_t n) {
    if (intr.size() != n)
      in.fail(intr_node, cam + ".intrinsics",
              "camera_model " + model + " takes " + std::to_string(n) + " intrinsics, got " +
                  std::to_string(intr.size()));
  };
  const auto expectCoeffs = [&](std::size_t n) {
    if (coeffs.size() != n)
      in.fail(node["distortion_coeffs"], cam + ".distortion_coeffs",
              "distortion_model " + distortion + " takes " + std::to_string(n) +
                  " coefficients, got " + std::to_string(coeffs.size()));
  };
  std::string ours;
  Eigen::VectorXd p;
  if (model == "ds" || model == "eucm") {
    expect(6);
    if (distortion != "none")
      in.fail(node["distortion_model"], cam + ".distortion_model",
              "camera_model " + model + " takes distortion_model none, got " + distortion);
    ours = model;
    p.resize(6);
    p << intr[2], intr[3], intr[4], intr[5], intr[0], intr[1];
  } else if (model == "pinhole") {
    expect(4);
    p.resize(8);
    if (distortion == "none") {
      ours = "pinhole";
      p << intr[0], intr[1], intr[2], intr[3], 0, 0, 0, 0;
    } else if (distortion == "radtan") {
      expectCoeffs(4);
      ours = "pinhole";
      p << intr[0], intr[1], intr[2], intr[3], coeffs[0], coeffs[1], coeffs[2], coeffs[3];
    } else if (distortion == "equidistant" || distortion == "equi") {
      expectCoeffs(4);
      ours = "kb4";
      p << intr[0], intr[1], intr[2], intr[3], coeffs[0], coeffs[1], coeffs[2], coeffs[3];
    } else {
      in.fail(node["distortion_model"], cam + ".distortion_model",
              "distortion_model " + distortion + " is not supported (none, radtan, equidistant)");
    }
  } else {
    in.fail(model_node, cam + ".camera_model",
            "camera_model " + model + " is not supported (ds, eucm, pinhole)");
  }
  const auto res = in.numbers(in.require(node, "resolution", cam + ".resolution"), cam + ".resolution", 2);
  std::string error;
  auto camera = GenericCamera::create(ours, p, &error);
  if (!camera) in.fail(intr_node, cam + ".intrinsics", error);
  return CameraCalibration{label, *camera, static_cast<int>(res[0]), static_cast<int>(res[1])};
}

SystemCalibration readKalibr(const YamlReader& in, const YAML::Node& root) {
  if (!root.IsMap() || !root["cam0"].IsDefined())
    in.fail(root, "cam0", "missing: not a kalibr camchain");
  if (root["cam2"].IsDefined())
    in.failAtKey(root, "cam2", "cam2", "telesphere takes one camera or a stereo pair (cam0, cam1)");
  SystemCalibration calib;
  calib.cameras.push_back(readKalibrCamera(in, root["cam0"], "cam0", "cam_l"));
  if (root["cam1"].IsDefined()) {
    calib.cameras.push_back(readKalibrCamera(in, root["cam1"], "cam1", "cam_r"));
    const Eigen::Isometry3d T_cam_r_cam_l =
        in.matrix4(in.require(root["cam1"], "T_cn_cnm1", "cam1.T_cn_cnm1"), "cam1.T_cn_cnm1");
    calib.T_cam_l_cam_r = T_cam_r_cam_l.inverse();
  }
  if (auto problem = calib.inconsistency())
    throw FileErrorException(FileError{in.path(), 0, problem->first, problem->second});
  return calib;
}

}  // namespace

FileResult<SystemCalibration> parseKalibrCamchain(const std::string& text, const std::string& path) {
  return detail::readYamlCalibration(text, path, readKalibr);
}

std::string toKalibrCamchain(const SystemCalibration& calib) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  for (std::size_t i = 0; i < calib.cameras.size(); ++i) {
    const auto& cam = calib.cameras[i];
    const Eigen::VectorXd p = cam.camera.params();
    const std::string model(cam.camera.modelName());
    out << YAML::Key << "cam" + std::to_string(i) << YAML::Value << YAML::BeginMap;
    if (i == 1 && calib.T_cam_l_cam_r) {
      const Eigen::Matrix4d M = calib.T_cam_l_cam_r->inverse().matrix();
      out << YAML::Key << "T_cn_cnm1" << YAML::Value << YAML::BeginSeq;
      for (int r = 0; r < 4; ++r)
        out << YAML::Flow << YAML::BeginSeq << M(r, 0) << M(r, 1) << M(r, 2) << M(r, 3) << YAML::EndSeq;
      out << YAML::EndSeq;
      out << YAML::Key << "cam_overlaps" << YAML::Value << YAML::Flow << std::vector<int>{0};
    } else if (calib.cameras.size() == 2) {
      out << YAML::Key << "cam_overlaps" << YAML::Value << YAML::Flow << std::vector<int>{1};
    }
    std::vector<double> intr, coeffs;
    std::string kalibr_model = model, distortion = "none";
    if (model == "ds" || model == "eucm") {
      intr = {p[4], p[5], p[0], p[1], p[2], p[3]};
    } else {
      kalibr_model = "pinhole";
      intr = {p[0], p[1], p[2], p[3]};
      coeffs = {p[4], p[5], p[6], p[7]};
      distortion = model == "kb4" ? "equidistant" : "radtan";
    }
    out << YAML::Key << "camera_model" << YAML::Value << kalibr_model;
    out << YAML::Key << "distortion_coeffs" << YAML::Value << YAML::Flow << coeffs;
    out << YAML::Key << "distortion_model" << YAML::Value << distortion;
    out << YAML::Key << "intrinsics" << YAML::Value << YAML::Flow << intr;
    out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << std::vector<int>{cam.width, cam.height};
    out << YAML::Key << "rostopic" << YAML::Value << "/" + cam.label + "/image_raw";
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace telesphere::calib
