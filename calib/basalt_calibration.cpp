// SPDX-License-Identifier: MIT
/// @brief Basalt calibration JSON import and export.
#include "calib/basalt_calibration.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace telesphere::calib {
namespace {

using nlohmann::json;

struct Reader {
  std::string path;

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw FileErrorException(FileError{path, 0, field, message});
  }
  const json& at(const json& parent, const char* key, const std::string& field) const {
    if (!parent.is_object() || !parent.contains(key)) fail(field, "missing");
    return parent.at(key);
  }
  double number(const json& j, const std::string& field) const {
    if (!j.is_number()) fail(field, "expected a number, got " + j.dump());
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(field, "not a finite number");
    return v;
  }
};

Eigen::Isometry3d readPose(const Reader& in, const json& j, const std::string& field) {
  const double qx = in.number(in.at(j, "qx", field + ".qx"), field + ".qx");
  const double qy = in.number(in.at(j, "qy", field + ".qy"), field + ".qy");
  const double qz = in.number(in.at(j, "qz", field + ".qz"), field + ".qz");
  const double qw = in.number(in.at(j, "qw", field + ".qw"), field + ".qw");
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  // Hand-edited files round quaternions to a few decimals: accept 1e-3 and normalise.
  if (std::abs(q.norm() - 1.0) > 1e-3)
    in.fail(field, "quaternion has norm " + std::to_string(q.norm()) + ", not 1");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() << in.number(in.at(j, "px", field + ".px"), field + ".px"),
      in.number(in.at(j, "py", field + ".py"), field + ".py"),
      in.number(in.at(j, "pz", field + ".pz"), field + ".pz");
  return T;
}

json writePose(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  return {{"px", T.translation().x()}, {"py", T.translation().y()}, {"pz", T.translation().z()},
          {"qx", q.x()}, {"qy", q.y()}, {"qz", q.z()}, {"qw", q.w()}};
}

CameraCalibration readBasaltCamera(const Reader& in, const json& intr, const json& res, int i) {
  const std::string field = "value0.intrinsics[" + std::to_string(i) + "]";
  const json& type_j = in.at(intr, "camera_type", field + ".camera_type");
  if (!type_j.is_string()) in.fail(field + ".camera_type", "expected a string");
  const std::string type = type_j.get<std::string>();
  const json& values = in.at(intr, "intrinsics", field + ".intrinsics");
  const auto get = [&](const char* name) {
    return in.number(in.at(values, name, field + ".intrinsics." + name), field + ".intrinsics." + name);
  };
  std::string model = type;
  std::vector<std::string_view> names = GenericCamera::paramNames(type);
  if (type == "pinhole") {
    names = {"fx", "fy", "cx", "cy"};
  } else if (type == "pinhole-radtan8") {
    model = "pinhole";
    names = GenericCamera::paramNames("pinhole");
    for (const char* k : {"k3", "k4", "k5", "k6"})
      if (get(k) != 0.0)
        in.fail(field + ".intrinsics." + k,
                "is " + std::to_string(get(k)) + "; the rational radtan8 terms k3..k6 are not "
                "modelled here (only k1 k2 p1 p2)");
  } else if (names.empty()) {
    in.fail(field + ".camera_type",
            "\"" + type + "\" is not supported (ds, eucm, kb4, pinhole, pinhole-radtan8)");
  }
  Eigen::VectorXd p = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(GenericCamera::paramNames(model).size()));
  for (std::size_t k = 0; k < names.size(); ++k) p[static_cast<Eigen::Index>(k)] = get(std::string(names[k]).c_str());
  std::string error;
  auto camera = GenericCamera::create(model, p, &error);
  if (!camera) in.fail(field + ".intrinsics." + error.substr(0, error.find(' ')), error);
  const std::string res_field = "value0.resolution[" + std::to_string(i) + "]";
  if (!res.is_array() || res.size() != 2) in.fail(res_field, "expected [width, height]");
  const char* const labels[] = {"cam_l", "cam_r"};
  return CameraCalibration{labels[i], *camera, static_cast<int>(in.number(res[0], res_field)),
                           static_cast<int>(in.number(res[1], res_field))};
}

SystemCalibration readBasalt(const Reader& in, const json& root) {
  const json& v = in.at(root, "value0", "value0");
  const json& intr = in.at(v, "intrinsics", "value0.intrinsics");
  const json& res = in.at(v, "resolution", "value0.resolution");
  if (!intr.is_array() || intr.empty()) in.fail("value0.intrinsics", "expected a list of cameras");
  if (intr.size() > 2) in.fail("value0.intrinsics", "telesphere takes one camera or a stereo pair");
  if (!res.is_array() || res.size() != intr.size())
    in.fail("value0.resolution", "expected one [width, height] per camera");
  SystemCalibration calib;
  for (std::size_t i = 0; i < intr.size(); ++i)
    calib.cameras.push_back(readBasaltCamera(in, intr[i], res[i], static_cast<int>(i)));
  if (calib.cameras.size() == 2) {
    const json& poses = in.at(v, "T_imu_cam", "value0.T_imu_cam");
    if (!poses.is_array() || poses.size() != 2) in.fail("value0.T_imu_cam", "expected one pose per camera");
    calib.T_cam_l_cam_r = readPose(in, poses[0], "value0.T_imu_cam[0]").inverse() *
                          readPose(in, poses[1], "value0.T_imu_cam[1]");
  }
  if (auto problem = calib.inconsistency()) in.fail(problem->first, problem->second);
  return calib;
}

}  // namespace

FileResult<SystemCalibration> parseBasaltCalibration(const std::string& text, const std::string& path) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    const auto upto = text.substr(0, std::min<std::size_t>(e.byte, text.size()));
    const int line = 1 + static_cast<int>(std::count(upto.begin(), upto.end(), '\n'));
    return FileError{path, line, "", std::string("JSON syntax: ") + e.what()};
  }
  try {
    return readBasalt(Reader{path}, root);
  } catch (const FileErrorException& e) {
    return e.error;
  }
}

std::string toBasaltCalibration(const SystemCalibration& calib) {
  json intrinsics = json::array(), resolution = json::array(), poses = json::array();
  for (std::size_t i = 0; i < calib.cameras.size(); ++i) {
    const auto& cam = calib.cameras[i];
    const std::string model(cam.camera.modelName());
    const Eigen::VectorXd p = cam.camera.params();
    const auto names = GenericCamera::paramNames(model);
    json values = json::object();
    for (std::size_t k = 0; k < names.size(); ++k) values[std::string(names[k])] = p[static_cast<Eigen::Index>(k)];
    std::string type = model;
    if (model == "pinhole") {
      if (p.tail<4>().isZero()) {
        for (const char* k : {"k1", "k2", "p1", "p2"}) values.erase(k);
      } else {
        type = "pinhole-radtan8";
        for (const char* k : {"k3", "k4", "k5", "k6"}) values[k] = 0.0;
        // Basalt's largest valid normalised radius; ours where finite, else effectively none.
        const double r_max = std::tan(cam.camera.maxAngle());
        values["rpmax"] = std::isfinite(r_max) && r_max < 1e6 ? r_max : 1e6;
      }
    }
    intrinsics.push_back({{"camera_type", type}, {"intrinsics", values}});
    resolution.push_back({cam.width, cam.height});
    poses.push_back(writePose(i == 0 || !calib.T_cam_l_cam_r ? Eigen::Isometry3d::Identity()
                                                             : *calib.T_cam_l_cam_r));
  }
  const json value0 = {{"T_imu_cam", poses},
                       {"intrinsics", intrinsics},
                       {"resolution", resolution},
                       {"vignette", json::array()},
                       {"calib_accel_bias", std::vector<double>(9, 0.0)},
                       {"calib_gyro_bias", std::vector<double>(12, 0.0)},
                       {"imu_update_rate", 0.0},
                       {"accel_noise_std", {0.0, 0.0, 0.0}},
                       {"gyro_noise_std", {0.0, 0.0, 0.0}},
                       {"accel_bias_std", {0.0, 0.0, 0.0}},
                       {"gyro_bias_std", {0.0, 0.0, 0.0}},
                       {"cam_time_offset_ns", 0}};
  return json{{"value0", value0}}.dump(4) + "\n";
}

}  // namespace telesphere::calib
