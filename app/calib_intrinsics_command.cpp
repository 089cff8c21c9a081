// SPDX-License-Identifier: MIT
/// @brief `telesphere-calib intrinsics` and `report` (see calib_intrinsics_command.h).
#include "app/calib_intrinsics_command.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <vector>

#include "app/calib_cli_io.h"
#include "calib/aprilgrid.h"
#include "calib/calibration_report.h"
#include "calib/intrinsic_calibration.h"
#include "calib/target_detection.h"

namespace telesphere::app {
namespace {

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

}  // namespace

CLI::App* addIntrinsicsCommand(CLI::App& app, IntrinsicsCommandOptions& intr) {
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
  return intrinsics;
}

int runIntrinsicsCommand(const IntrinsicsCommandOptions& args) {
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

CLI::App* addReportCommand(CLI::App& app, ReportCommandOptions& o) {
  CLI::App* report = app.add_subcommand("report", "summary and coverage pictures of an intrinsic calibration");
  report->add_option("--report", o.report, "report JSON written by `intrinsics`")
      ->required()
      ->check(CLI::ExistingFile);
  report->add_option("--coverage", o.coverage_prefix, "write PREFIX_cam_l.png (and _cam_r) coverage pictures");
  return report;
}

int runReportCommand(const ReportCommandOptions& o) {
  const auto report = calib::loadIntrinsicReport(o.report);
  if (!report) {
    std::cerr << "telesphere-calib: " << report.error().describe() << "\n";
    return 1;
  }
  std::cout << calib::kalibrStyleSummary(*report);
  if (o.coverage_prefix.empty()) return 0;
  for (const auto& cam : report->cameras) {
    const std::string path = o.coverage_prefix + "_" + cam.calibration.label + ".png";
    if (!calib::writeGrayImage(calib::coverageImage(cam), path)) {
      std::cerr << "telesphere-calib: cannot write " << path << "\n";
      return 1;
    }
    std::cerr << "wrote " << path << "\n";
  }
  return 0;
}

}  // namespace telesphere::app
