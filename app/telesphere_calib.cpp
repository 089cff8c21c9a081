// SPDX-License-Identifier: MIT
/// @brief telesphere-calib: calibration and camera-model tools.
///   model project|unproject --calib FILE --camera N   stdin → stdout, one line per line
///   convert --calib FILE --out FILE --format telesphere|kalibr|basalt
///   info --calib FILE                                 models, parameters, fields of view
/// --calib takes our calibration YAML, a kalibr camchain.yaml or a Basalt calibration JSON.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

#include "calib/calibration_file.h"

namespace {

using telesphere::calib::CameraCalibration;
using telesphere::calib::SystemCalibration;

std::optional<SystemCalibration> load(const std::string& path) {
  auto result = telesphere::calib::loadCalibrationFile(path);
  if (!result) {
    std::cerr << "telesphere-calib: " << result.error().describe() << "\n";
    return std::nullopt;
  }
  return *result;
}

/// Reads stdin line by line; blank lines and lines starting with '#' pass through unchanged so
/// that output line k answers input line k. A line that does not hold `count` numbers answers
/// "invalid" and is reported on stderr.
int transformLines(int count, const std::function<std::string(const double*)>& f) {
  std::string line;
  int line_number = 0, bad = 0;
  while (std::getline(std::cin, line)) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') {
      std::cout << line << '\n';
      continue;
    }
    std::istringstream in(line);
    double v[3];
    int n = 0;
    while (n < count && in >> v[n]) ++n;
    std::string extra;
    if (n != count || (in >> extra)) {
      std::cerr << "telesphere-calib: stdin line " << line_number << ": expected " << count
                << " numbers, got \"" << line << "\"\n";
      std::cout << "invalid\n";
      ++bad;
      continue;
    }
    std::cout << f(v) << '\n';
  }
  std::cout.flush();
  return bad == 0 ? 0 : 3;
}

std::string format(std::initializer_list<double> values) {
  std::string out;
  char buf[32];
  for (double v : values) {
    std::snprintf(buf, sizeof buf, "%.17g", v);
    out += (out.empty() ? "" : " ") + std::string(buf);
  }
  return out;
}

/// Horizontal field of view covered by the image: the angles of the outermost valid pixels of
/// the centre row, left and right, added.
double horizontalFovDeg(const CameraCalibration& cam) {
  const double v = cam.camera.params()[3];
  double left = NAN, right = NAN;
  for (int u = 0; u < cam.width && std::isnan(left); ++u) {
    Eigen::Vector3d d;
    if (cam.camera.unproject(Eigen::Vector2d(u, v), d)) left = std::acos(d.z());
  }
  for (int u = cam.width - 1; u >= 0 && std::isnan(right); --u) {
    Eigen::Vector3d d;
    if (cam.camera.unproject(Eigen::Vector2d(u, v), d)) right = std::acos(d.z());
  }
  return (left + right) * 180.0 / M_PI;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"telesphere-calib: calibration and camera-model tools"};
  app.require_subcommand(1);

  std::string calib_path;
  int camera_index = 0;
  CLI::App* model = app.add_subcommand("model", "run a calibrated camera model on stdin");
  model->require_subcommand(1);
  CLI::App* project = model->add_subcommand(
      "project", "lines 'x y z' (metres, camera optical frame) → 'u v' (px) or 'invalid'");
  CLI::App* unproject = model->add_subcommand(
      "unproject", "lines 'u v' (px) → unit bearing 'x y z' or 'invalid'");
  for (CLI::App* sub : {project, unproject}) {
    sub->add_option("--calib", calib_path, "calibration file (ours, kalibr camchain or Basalt JSON)")
        ->required()
        ->check(CLI::ExistingFile);
    sub->add_option("--camera", camera_index, "camera index: 0 = cam_l (cam0), 1 = cam_r (cam1)")
        ->capture_default_str();
  }

  std::string out_path, format_name = "telesphere";
  CLI::App* convert = app.add_subcommand("convert", "convert between calibration formats");
  convert->add_option("--calib", calib_path, "input calibration file (any format)")
      ->required()
      ->check(CLI::ExistingFile);
  convert->add_option("--out", out_path, "output file")->required();
  convert->add_option("--format", format_name, "output format")
      ->check(CLI::IsMember({"telesphere", "kalibr", "basalt"}))
      ->capture_default_str();

  CLI::App* info = app.add_subcommand("info", "models, parameters and fields of view of a calibration");
  info->add_option("--calib", calib_path, "calibration file (any format)")->required()->check(CLI::ExistingFile);

  CLI11_PARSE(app, argc, argv);

  const auto calib = load(calib_path);
  if (!calib) return 1;

  if (model->parsed()) {
    if (camera_index < 0 || camera_index >= static_cast<int>(calib->cameras.size())) {
      std::cerr << "telesphere-calib: --camera " << camera_index << " does not exist: "
                << calib_path << " has " << calib->cameras.size() << " camera(s)\n";
      return 2;
    }
    const auto& camera = calib->cameras[static_cast<std::size_t>(camera_index)].camera;
    if (project->parsed()) {
      return transformLines(3, [&](const double* v) {
        Eigen::Vector2d px;
        return camera.project(Eigen::Vector3d(v[0], v[1], v[2]), px) ? format({px.x(), px.y()})
                                                                     : std::string("invalid");
      });
    }
    return transformLines(2, [&](const double* v) {
      Eigen::Vector3d d;
      return camera.unproject(Eigen::Vector2d(v[0], v[1]), d) ? format({d.x(), d.y(), d.z()})
                                                              : std::string("invalid");
    });
  }
  if (convert->parsed()) {
    const auto format = *telesphere::calib::parseFormatName(format_name);
    if (auto error = telesphere::calib::saveCalibrationFile(*calib, out_path, format)) {
      std::cerr << "telesphere-calib: " << error->describe() << "\n";
      return 1;
    }
    std::cerr << "wrote " << out_path << " (" << format_name << ")\n";
    return 0;
  }
  if (info->parsed()) {
    for (const auto& cam : calib->cameras) {
      std::cout << cam.label << ": " << cam.camera.modelName() << " " << cam.width << "x"
                << cam.height << "\n  ";
      const auto names = telesphere::calib::GenericCamera::paramNames(cam.camera.modelName());
      const Eigen::VectorXd p = cam.camera.params();
      for (std::size_t i = 0; i < names.size(); ++i)
        std::cout << names[i] << "=" << p[static_cast<Eigen::Index>(i)] << (i + 1 < names.size() ? " " : "\n");
      std::cout << "  model field of view " << 2 * cam.camera.maxAngle() * 180 / M_PI
                << " deg, image horizontal field of view " << horizontalFovDeg(cam) << " deg\n";
    }
    const std::pair<const char*, const std::optional<Eigen::Isometry3d>*> transforms[] = {
        {"T_cam_l_cam_r", &calib->T_cam_l_cam_r},
        {"T_flange_cam_l", &calib->T_flange_cam_l},
        {"T_robot_mount", &calib->T_robot_mount},
        {"T_wrist_marker", &calib->T_wrist_marker}};
    for (const auto& [name, T] : transforms) {
      std::cout << name << ": ";
      if (*T)
        std::cout << "t = [" << (*T)->translation().transpose() << "] m, rotation "
                  << Eigen::AngleAxisd((*T)->linear()).angle() * 180 / M_PI << " deg\n";
      else
        std::cout << "not calibrated\n";
    }
  }
  return 0;
}
