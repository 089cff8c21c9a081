// SPDX-License-Identifier: MIT
/// @brief telesphere-calib: calibration and camera-model tools.
///   model project|unproject --calib FILE --camera N   stdin → stdout, one line per line
///   convert --calib FILE --out FILE --format telesphere|kalibr|basalt
///   info --calib FILE                                 models, parameters, fields of view
///   intrinsics --images DIR [--images-right DIR] --target aprilgrid.yaml --model ds --out FILE
///                                                     calibrate a camera or the stereo pair
///   handeye --samples FILE --calib FILE --out FILE    T_flange_cam_l, T_robot_mount, T_wrist_marker
///   report --report FILE [--coverage PREFIX]          kalibr-style summary and coverage pictures
/// --calib takes our calibration YAML, a kalibr camchain.yaml or a Basalt calibration JSON.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

#include "calib/aprilgrid.h"
#include "calib/calibration_file.h"
#include "calib/calibration_report.h"
#include "calib/hand_eye_samples.h"
#include "calib/intrinsic_calibration.h"
#include "calib/target_detection.h"
#ifdef TELESPHERE_CALIB_HAS_ROBOT
#include "robot/xarm6_kinematics.h"
#endif

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

void progressLine(const std::string& line) { std::cerr << line << "\n"; }

/// Image files of a folder (png, jpg, jpeg, bmp, tif, tiff, pgm), sorted by name.
std::vector<std::filesystem::path> imageFiles(const std::string& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (entry.is_regular_file() &&
        (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tif" ||
         ext == ".tiff" || ext == ".pgm"))
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

struct IntrinsicsArgs {
  std::string images, images_right, target, model = "ds", out, format = "telesphere", report;
  int min_tags = 4;
};

int runIntrinsics(const IntrinsicsArgs& args) {
  namespace calib = telesphere::calib;
  const auto grid = calib::loadAprilGrid(args.target);
  if (!grid) {
    std::cerr << "telesphere-calib: " << grid.error().describe() << "\n";
    return 1;
  }
  std::vector<std::string> dirs = {args.images};
  if (!args.images_right.empty()) dirs.push_back(args.images_right);
  std::vector<std::vector<std::filesystem::path>> files;
  for (const auto& dir : dirs) files.push_back(imageFiles(dir));
  if (files.size() == 2 && files[0].size() != files[1].size()) {
    std::cerr << "telesphere-calib: " << args.images << " has " << files[0].size() << " images but "
              << args.images_right << " has " << files[1].size() << " (stereo pairs are matched by sorted name)\n";
    return 1;
  }
  if (files[0].empty()) {
    std::cerr << "telesphere-calib: no images in " << args.images << "\n";
    return 1;
  }
  calib::DetectionOptions detection;
  detection.min_tags = args.min_tags;
  std::vector<calib::CameraViews> cameras(files.size());
  for (std::size_t c = 0; c < files.size(); ++c) {
    cameras[c].label = c == 0 ? "cam_l" : "cam_r";
    cameras[c].model = args.model;
    for (std::size_t i = 0; i < files[c].size(); ++i) {
      const auto image = calib::readGrayImage(files[c][i].string());
      if (!image) {
        std::cerr << "telesphere-calib: cannot read the image " << files[c][i].string() << "\n";
        return 1;
      }
      if (cameras[c].width == 0) {
        cameras[c].width = image->width;
        cameras[c].height = image->height;
      } else if (image->width != cameras[c].width || image->height != cameras[c].height) {
        std::cerr << "telesphere-calib: " << files[c][i].string() << " is " << image->width << "x"
                  << image->height << ", the first image was " << cameras[c].width << "x"
                  << cameras[c].height << "\n";
        return 1;
      }
      cameras[c].views.push_back(calib::detectAprilGrid(*image, *grid, detection));
      std::cerr << "detecting " << cameras[c].label << " " << (i + 1) << "/" << files[c].size() << " "
                << files[c][i].filename().string() << ": " << cameras[c].views.back().tags_detected
                << " tags, " << cameras[c].views.back().corner_ids.size() << " corners used\n";
    }
  }
  calib::IntrinsicOptions options;
  options.progress = progressLine;
  const auto result = calib::calibrateIntrinsics(*grid, cameras, options);
  if (!result) {
    std::cerr << "telesphere-calib: " << result.failure().message << "\n";
    return 2;
  }
  std::cout << calib::kalibrStyleSummary(*result);
  for (const auto& cam : result->cameras)
    if (!cam.degeneracy_warning.empty())
      std::cerr << "telesphere-calib: WARNING: " << cam.degeneracy_warning << "\n";
  const auto format = *calib::parseFormatName(args.format);
  if (auto error = calib::saveCalibrationFile(result->toSystemCalibration(), args.out, format)) {
    std::cerr << "telesphere-calib: " << error->describe() << "\n";
    return 1;
  }
  const std::string report = args.report.empty() ? args.out + ".report.json" : args.report;
  if (auto error = calib::saveIntrinsicReport(*result, report)) {
    std::cerr << "telesphere-calib: " << error->describe() << "\n";
    return 1;
  }
  std::cerr << "wrote " << args.out << " (" << args.format << ") and " << report << "\n";
  return 0;
}

/// The head arm's forward kinematics for sample files with joint angles (q_head): the xArm 6
/// model of robot/xarm6_kinematics.h when the robot library is part of the build.
telesphere::calib::HeadArmForwardKinematics headArmForwardKinematics() {
#ifdef TELESPHERE_CALIB_HAS_ROBOT
  return [kinematics = telesphere::robot::Xarm6Kinematics()](const std::vector<double>& q, std::string* error)
             -> std::optional<Eigen::Isometry3d> {
    if (q.size() != static_cast<std::size_t>(telesphere::robot::Xarm6Kinematics::kDof)) {
      *error = "expected " + std::to_string(telesphere::robot::Xarm6Kinematics::kDof) +
               " xArm 6 joint angles (rad), got " + std::to_string(q.size());
      return std::nullopt;
    }
    const telesphere::robot::JointVector joints = Eigen::Map<const telesphere::robot::JointVector>(q.data());
    if (!kinematics.withinLimits(joints, 1e-6)) {
      *error = "the joint angles are outside the xArm 6 joint limits";
      return std::nullopt;
    }
    return kinematics.forward(joints);
  };
#else
  return {};
#endif
}

int runHandEye(const std::string& samples_path, const std::string& calib_path, const std::string& out,
               const std::string& format_name) {
  namespace calib = telesphere::calib;
  auto system = load(calib_path);
  if (!system) return 1;
  const auto file = calib::loadHandEyeSamples(samples_path, progressLine, headArmForwardKinematics());
  if (!file) {
    std::cerr << "telesphere-calib: " << file.error().describe() << "\n";
    return 1;
  }
  calib::HandEyeOptions options;
  options.progress = progressLine;
  // The file's T_flange_cam_l is a second start for the solve (and the only one below
  // kClosedFormMinSamples samples), as in the console's wizard.
  options.T_flange_cam_l_guess = system->T_flange_cam_l;
  const auto result = calib::calibrateHandEye(*system, file->marker_size, file->samples, options);
  if (!result) {
    std::cerr << "telesphere-calib: " << result.failure().message << "\n";
    return 2;
  }
  std::printf("hand-eye: %d samples, RMS cam_l %.4f px, cam_r %.4f px; rotation axes spread head %.1f deg, wrist %.1f deg\n",
              result->samples_used, result->rms_px_l, result->rms_px_r,
              result->identifiability.head_axis_spread_deg, result->identifiability.wrist_axis_spread_deg);
  const std::pair<const char*, const Eigen::Isometry3d*> transforms[] = {
      {"T_flange_cam_l", &result->T_flange_cam_l},
      {"T_robot_mount", &result->T_robot_mount},
      {"T_wrist_marker", &result->T_wrist_marker}};
  for (const auto& [name, T] : transforms)
    std::cout << name << ":\n" << T->matrix() << "\n";
  system->T_flange_cam_l = result->T_flange_cam_l;
  system->T_robot_mount = result->T_robot_mount;
  system->T_wrist_marker = result->T_wrist_marker;
  if (auto error = calib::saveCalibrationFile(*system, out, *calib::parseFormatName(format_name))) {
    std::cerr << "telesphere-calib: " << error->describe() << "\n";
    return 1;
  }
  std::cerr << "wrote " << out << " (" << format_name << ")\n";
  return 0;
}

int runReport(const std::string& report_path, const std::string& coverage_prefix) {
  namespace calib = telesphere::calib;
  const auto report = calib::loadIntrinsicReport(report_path);
  if (!report) {
    std::cerr << "telesphere-calib: " << report.error().describe() << "\n";
    return 1;
  }
  std::cout << calib::kalibrStyleSummary(*report);
  if (coverage_prefix.empty()) return 0;
  for (const auto& cam : report->cameras) {
    const std::string path = coverage_prefix + "_" + cam.calibration.label + ".png";
    if (!calib::writeGrayImage(calib::coverageImage(cam), path)) {
      std::cerr << "telesphere-calib: cannot write " << path << "\n";
      return 1;
    }
    std::cerr << "wrote " << path << "\n";
  }
  return 0;
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

  IntrinsicsArgs intr;
  CLI::App* intrinsics = app.add_subcommand(
      "intrinsics", "calibrate a camera (or the stereo pair) from images of a kalibr Aprilgrid");
  intrinsics->add_option("--images", intr.images, "folder of images of cam_l (cam0)")
      ->required()
      ->check(CLI::ExistingDirectory);
  intrinsics->add_option("--images-right", intr.images_right,
                         "folder of images of cam_r taken with those of --images (matched by sorted name)")
      ->check(CLI::ExistingDirectory);
  intrinsics->add_option("--target", intr.target, "kalibr target YAML (aprilgrid)")
      ->required()
      ->check(CLI::ExistingFile);
  intrinsics->add_option("--model", intr.model, "camera model")
      ->check(CLI::IsMember({"ds", "eucm", "kb4", "pinhole"}))
      ->capture_default_str();
  intrinsics->add_option("--out", intr.out, "output calibration file")->required();
  intrinsics->add_option("--format", intr.format, "output format")
      ->check(CLI::IsMember({"telesphere", "kalibr", "basalt"}))
      ->capture_default_str();
  intrinsics->add_option("--report", intr.report, "report JSON (default: OUT.report.json)");
  intrinsics->add_option("--min-tags", intr.min_tags, "tags a view needs")->capture_default_str();

  std::string samples_path;
  CLI::App* handeye = app.add_subcommand(
      "handeye", "hand-eye calibration (T_flange_cam_l, T_robot_mount, T_wrist_marker) from a sample file");
  handeye->add_option("--samples", samples_path, "sample file (YAML, see calib/hand_eye_samples.h)")
      ->required()
      ->check(CLI::ExistingFile);
  handeye->add_option("--calib", calib_path, "calibration with the cameras' intrinsics (any format)")
      ->required()
      ->check(CLI::ExistingFile);
  handeye->add_option("--out", out_path, "output calibration file (the input plus the hand-eye transforms)")
      ->required();
  handeye->add_option("--format", format_name, "output format")
      ->check(CLI::IsMember({"telesphere", "kalibr", "basalt"}))
      ->capture_default_str();

  std::string report_path, coverage_prefix;
  CLI::App* report = app.add_subcommand("report", "summary and coverage pictures of an intrinsic calibration");
  report->add_option("--report", report_path, "report JSON written by `intrinsics`")
      ->required()
      ->check(CLI::ExistingFile);
  report->add_option("--coverage", coverage_prefix, "write PREFIX_cam_l.png (and _cam_r) coverage pictures");

  CLI11_PARSE(app, argc, argv);

  if (intrinsics->parsed()) return runIntrinsics(intr);
  if (handeye->parsed()) return runHandEye(samples_path, calib_path, out_path, format_name);
  if (report->parsed()) return runReport(report_path, coverage_prefix);

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
