// SPDX-License-Identifier: MIT
/// @brief The calibration-file tools of `telesphere-calib` (see calib_file_commands.h).
#include "app/calib_file_commands.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <sstream>

#include "app/calib_cli_io.h"

namespace telesphere::app {
namespace {

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
double horizontalFovDeg(const calib::CameraCalibration& cam) {
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

/// `model project|unproject`: the camera model on stdin, one answer per line.
int runModel(const CalibrationFileCommands& c, const CalibrationFileCommandOptions& o,
             const calib::SystemCalibration& system) {
  if (o.camera < 0 || o.camera >= static_cast<int>(system.cameras.size())) {
    std::cerr << "telesphere-calib: --camera " << o.camera << " does not exist: " << o.calib << " has "
              << system.cameras.size() << " camera(s)\n";
    return 2;
  }
  const auto& camera = system.cameras[static_cast<std::size_t>(o.camera)].camera;
  if (c.project->parsed()) {
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

/// `convert`: the same calibration in another format.
int runConvert(const CalibrationFileCommandOptions& o, const calib::SystemCalibration& system) {
  if (auto error = calib::saveCalibrationFile(system, o.out, *calib::parseFormatName(o.format))) {
    std::cerr << "telesphere-calib: " << error->describe() << "\n";
    return 1;
  }
  std::cerr << "wrote " << o.out << " (" << o.format << ")\n";
  return 0;
}

/// `info`: each camera's model, parameters and fields of view; the transforms present.
int runInfo(const calib::SystemCalibration& system) {
  for (const auto& cam : system.cameras) {
    std::cout << cam.label << ": " << cam.camera.modelName() << " " << cam.width << "x" << cam.height << "\n  ";
    const auto names = calib::GenericCamera::paramNames(cam.camera.modelName());
    const Eigen::VectorXd p = cam.camera.params();
    for (std::size_t i = 0; i < names.size(); ++i)
      std::cout << names[i] << "=" << p[static_cast<Eigen::Index>(i)] << (i + 1 < names.size() ? " " : "\n");
    std::cout << "  model field of view " << 2 * cam.camera.maxAngle() * 180 / M_PI
              << " deg, image horizontal field of view " << horizontalFovDeg(cam) << " deg\n";
  }
  const std::pair<const char*, const std::optional<Eigen::Isometry3d>*> transforms[] = {
      {"T_cam_l_cam_r", &system.T_cam_l_cam_r},
      {"T_flange_cam_l", &system.T_flange_cam_l},
      {"T_robot_mount", &system.T_robot_mount},
      {"T_wrist_marker", &system.T_wrist_marker}};
  for (const auto& [name, T] : transforms) {
    std::cout << name << ": ";
    if (*T)
      std::cout << "t = [" << (*T)->translation().transpose() << "] m, rotation "
                << Eigen::AngleAxisd((*T)->linear()).angle() * 180 / M_PI << " deg\n";
    else
      std::cout << "not calibrated\n";
  }
  return 0;
}

}  // namespace

CalibrationFileCommands addCalibrationFileCommands(CLI::App& app, CalibrationFileCommandOptions& o) {
  CalibrationFileCommands c{};
  c.model = app.add_subcommand("model", "run a calibrated camera model on stdin");
  c.model->require_subcommand(1);
  c.project = c.model->add_subcommand(
      "project", "lines 'x y z' (metres, camera optical frame) → 'u v' (px) or 'invalid'");
  c.unproject = c.model->add_subcommand("unproject", "lines 'u v' (px) → unit bearing 'x y z' or 'invalid'");
  for (CLI::App* sub : {c.project, c.unproject}) {
    sub->add_option("--calib", o.calib, "calibration file (ours, kalibr camchain or Basalt JSON)")
        ->required()
        ->check(CLI::ExistingFile);
    sub->add_option("--camera", o.camera, "camera index: 0 = cam_l (cam0), 1 = cam_r (cam1)")
        ->capture_default_str();
  }
  c.convert = app.add_subcommand("convert", "convert between calibration formats");
  c.convert->add_option("--calib", o.calib, "input calibration file (any format)")
      ->required()
      ->check(CLI::ExistingFile);
  c.convert->add_option("--out", o.out, "output file")->required();
  c.convert->add_option("--format", o.format, "output format")
      ->check(CLI::IsMember({"telesphere", "kalibr", "basalt"}))
      ->capture_default_str();
  c.info = app.add_subcommand("info", "models, parameters and fields of view of a calibration");
  c.info->add_option("--calib", o.calib, "calibration file (any format)")->required()->check(CLI::ExistingFile);
  return c;
}

int runCalibrationFileCommand(const CalibrationFileCommands& c, const CalibrationFileCommandOptions& o) {
  const auto system = loadCalibrationOrSay(o.calib);
  if (!system) return 1;
  if (c.model->parsed()) return runModel(c, o, *system);
  if (c.convert->parsed()) return runConvert(o, *system);
  return runInfo(*system);
}

}  // namespace telesphere::app
