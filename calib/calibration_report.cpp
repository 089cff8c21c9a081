// SPDX-License-Identifier: MIT
/// @brief Intrinsic calibration report (see calibration_report.h).
#include "calib/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace telesphere::calib {
namespace {

constexpr int kCells = 16;

std::vector<int> cellCounts(const CameraIntrinsicResult& camera) {
  std::vector<int> counts(kCells * kCells, 0);
  const int w = camera.calibration.width, h = camera.calibration.height;
  for (const auto& r : camera.residuals) {
    const int cu = std::clamp(static_cast<int>(r.px.x() * kCells / w), 0, kCells - 1);
    const int cv = std::clamp(static_cast<int>(r.px.y() * kCells / h), 0, kCells - 1);
    ++counts[static_cast<std::size_t>(cv * kCells + cu)];
  }
  return counts;
}

nlohmann::json poseJson(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  return {{"translation", {T.translation().x(), T.translation().y(), T.translation().z()}},
          {"rotation_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

Eigen::Isometry3d poseFromJson(const nlohmann::json& j) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const auto t = j.at("translation").get<std::vector<double>>();
  const auto q = j.at("rotation_xyzw").get<std::vector<double>>();
  T.linear() = Eigen::Quaterniond(q.at(3), q.at(0), q.at(1), q.at(2)).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(t.at(0), t.at(1), t.at(2));
  return T;
}

}  // namespace

double coverageFraction(const CameraIntrinsicResult& camera) {
  const auto counts = cellCounts(camera);
  return double(std::count_if(counts.begin(), counts.end(), [](int c) { return c > 0; })) / counts.size();
}

GrayImage coverageImage(const CameraIntrinsicResult& camera, int scale) {
  const int w = camera.calibration.width, h = camera.calibration.height;
  const int W = std::max(1, w / scale), H = std::max(1, h / scale);
  cv::Mat img(H, W, CV_8UC1, cv::Scalar(0));
  const auto counts = cellCounts(camera);
  const int max_count = std::max(1, *std::max_element(counts.begin(), counts.end()));
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      Eigen::Vector3d d;
      if (!camera.calibration.camera.unproject(Eigen::Vector2d(u * scale, v * scale), d)) continue;
      const int cu = std::min(kCells - 1, u * kCells / W), cv_ = std::min(kCells - 1, v * kCells / H);
      const int c = counts[static_cast<std::size_t>(cv_ * kCells + cu)];
      img.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(c == 0 ? 30 : 60 + 100 * c / max_count);
    }
  }
  for (const auto& r : camera.residuals) {
    const cv::Point2d p(r.px.x() / scale, r.px.y() / scale);
    const cv::Point2d e(20.0 * r.error_px.x() / scale, 20.0 * r.error_px.y() / scale);
    cv::line(img, p, p + e, cv::Scalar(200), 1, cv::LINE_AA);
    cv::circle(img, p, 1, cv::Scalar(255), cv::FILLED);
  }
  GrayImage out(W, H);
  for (int v = 0; v < H; ++v) std::copy_n(img.ptr<std::uint8_t>(v), W, &out.pixels[static_cast<std::size_t>(v) * W]);
  return out;
}

std::string kalibrStyleSummary(const IntrinsicResult& result) {
  std::ostringstream os;
  char buf[256];
  for (std::size_t c = 0; c < result.cameras.size(); ++c) {
    const auto& cam = result.cameras[c];
    const auto names = GenericCamera::paramNames(cam.calibration.camera.modelName());
    const Eigen::VectorXd p = cam.calibration.camera.params();
    os << "cam" << c << " (" << cam.calibration.label << ")\n";
    os << "  camera model: " << cam.calibration.camera.modelName() << ", resolution "
       << cam.calibration.width << "x" << cam.calibration.height << "\n";
    for (std::size_t i = 0; i < names.size(); ++i) {
      std::snprintf(buf, sizeof buf, "  %-6s %14.6f", std::string(names[i]).c_str(), p[static_cast<Eigen::Index>(i)]);
      os << buf;
      if (i < cam.param_stddev.size()) {
        std::snprintf(buf, sizeof buf, "  +- %.6f", cam.param_stddev[i]);
        os << buf;
      }
      os << "\n";
    }
    std::snprintf(buf, sizeof buf,
                  "  reprojection error: RMS %.4f px, mean %.4f px over %d corners in %d views\n",
                  cam.rms_px, cam.mean_px, cam.corners, cam.views_used);
    os << buf;
    std::snprintf(buf, sizeof buf, "  coverage: %.0f%% of a 16x16 grid of image cells hold corners\n",
                  100.0 * coverageFraction(cam));
    os << buf;
    if (std::isfinite(cam.focal_distortion_correlation)) {
      std::snprintf(buf, sizeof buf, "  separability: focal length vs distortion multiple correlation %.6f\n",
                    cam.focal_distortion_correlation);
      os << buf;
    }
    if (!cam.degeneracy_warning.empty()) os << "  WARNING: " << cam.degeneracy_warning << "\n";
    auto views = cam.per_view;
    std::sort(views.begin(), views.end(), [](const ViewError& a, const ViewError& b) { return a.rms_px > b.rms_px; });
    os << "  worst views:";
    for (std::size_t i = 0; i < std::min<std::size_t>(5, views.size()); ++i) {
      std::snprintf(buf, sizeof buf, " #%d %.3f px (%d corners);", views[i].view, views[i].rms_px, views[i].corners);
      os << buf;
    }
    os << "\n";
  }
  if (result.T_cam_l_cam_r) {
    const Eigen::Isometry3d& T = *result.T_cam_l_cam_r;
    os << "T_cam_l_cam_r (cam1 to cam0):\n" << T.matrix() << "\n";
    std::snprintf(buf, sizeof buf, "  baseline %.6f m, rotation %.4f deg\n", T.translation().norm(),
                  Eigen::AngleAxisd(T.linear()).angle() * 180 / M_PI);
    os << buf;
  }
  std::snprintf(buf, sizeof buf, "solve: cost %.6g -> %.6g in %d iterations, %.2f s\n",
                result.initial_cost, result.final_cost, result.iterations, result.solve_seconds);
  os << buf;
  return os.str();
}

std::optional<FileError> saveIntrinsicReport(const IntrinsicResult& result, const std::string& path) {
  nlohmann::json j;
  j["version"] = 1;
  for (const auto& cam : result.cameras) {
    nlohmann::json c;
    c["label"] = cam.calibration.label;
    c["model"] = std::string(cam.calibration.camera.modelName());
    const Eigen::VectorXd p = cam.calibration.camera.params();
    c["params"] = std::vector<double>(p.data(), p.data() + p.size());
    c["param_stddev"] = cam.param_stddev;
    if (std::isfinite(cam.focal_distortion_correlation))
      c["focal_distortion_correlation"] = cam.focal_distortion_correlation;
    if (!cam.degeneracy_warning.empty()) c["degeneracy_warning"] = cam.degeneracy_warning;
    for (Eigen::Index i = 0; i < cam.param_correlation.rows(); ++i) {
      const Eigen::VectorXd row = cam.param_correlation.row(i).transpose();
      c["param_correlation"].push_back(std::vector<double>(row.data(), row.data() + row.size()));
    }
    c["resolution"] = {cam.calibration.width, cam.calibration.height};
    c["rms_px"] = cam.rms_px;
    c["mean_px"] = cam.mean_px;
    c["corners"] = cam.corners;
    for (const auto& v : cam.per_view) c["per_view"].push_back({v.view, v.corners, v.rms_px});
    for (const auto& r : cam.residuals)
      c["residuals"].push_back({r.view, r.corner_id, r.px.x(), r.px.y(), r.error_px.x(), r.error_px.y()});
    j["cameras"].push_back(c);
  }
  if (result.T_cam_l_cam_r) j["T_cam_l_cam_r"] = poseJson(*result.T_cam_l_cam_r);
  j["initial_cost"] = result.initial_cost;
  j["final_cost"] = result.final_cost;
  j["iterations"] = result.iterations;
  j["solve_seconds"] = result.solve_seconds;
  std::ofstream out(path);
  if (!(out << j.dump(1) << "\n")) return FileError{path, 0, "", "cannot write the report"};
  return std::nullopt;
}

FileResult<IntrinsicResult> loadIntrinsicReport(const std::string& path) {
  std::ifstream in(path);
  if (!in) return FileError{path, 0, "", "cannot open the report"};
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    IntrinsicResult result;
    for (const auto& c : j.at("cameras")) {
      const auto params = c.at("params").get<std::vector<double>>();
      std::string error;
      auto camera = GenericCamera::create(c.at("model").get<std::string>(),
                                          Eigen::Map<const Eigen::VectorXd>(params.data(), static_cast<Eigen::Index>(params.size())),
                                          &error);
      if (!camera) return FileError{path, 0, "cameras.params", error};
      CameraIntrinsicResult cam{CameraCalibration{c.at("label").get<std::string>(), *camera,
                                                  c.at("resolution").at(0).get<int>(),
                                                  c.at("resolution").at(1).get<int>()}};
      cam.param_stddev = c.at("param_stddev").get<std::vector<double>>();
      cam.rms_px = c.at("rms_px").get<double>();
      cam.focal_distortion_correlation = c.value("focal_distortion_correlation", double(NAN));
      cam.degeneracy_warning = c.value("degeneracy_warning", std::string());
      if (c.contains("param_correlation")) {
        const auto rows = c["param_correlation"].get<std::vector<std::vector<double>>>();
        const auto n = static_cast<Eigen::Index>(rows.size());
        cam.param_correlation.resize(n, n);
        for (Eigen::Index i = 0; i < n; ++i) {
          if (rows[static_cast<std::size_t>(i)].size() != rows.size())
            return FileError{path, 0, "cameras.param_correlation", "expected a square matrix"};
          for (Eigen::Index j = 0; j < n; ++j) cam.param_correlation(i, j) = rows[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
        }
      }
      cam.mean_px = c.at("mean_px").get<double>();
      cam.corners = c.at("corners").get<int>();
      if (c.contains("per_view"))
        for (const auto& v : c["per_view"]) cam.per_view.push_back({v.at(0).get<int>(), v.at(1).get<int>(), v.at(2).get<double>()});
      cam.views_used = static_cast<int>(cam.per_view.size());
      if (c.contains("residuals"))
        for (const auto& r : c["residuals"])
          cam.residuals.push_back({r.at(0).get<int>(), r.at(1).get<int>(),
                                   Eigen::Vector2d(r.at(2).get<double>(), r.at(3).get<double>()),
                                   Eigen::Vector2d(r.at(4).get<double>(), r.at(5).get<double>())});
      result.cameras.push_back(std::move(cam));
    }
    if (j.contains("T_cam_l_cam_r")) result.T_cam_l_cam_r = poseFromJson(j["T_cam_l_cam_r"]);
    result.initial_cost = j.value("initial_cost", 0.0);
    result.final_cost = j.value("final_cost", 0.0);
    result.iterations = j.value("iterations", 0);
    result.solve_seconds = j.value("solve_seconds", 0.0);
    return result;
  } catch (const nlohmann::json::exception& e) {
    return FileError{path, 0, "", std::string("not a calibration report: ") + e.what()};
  }
}

}  // namespace telesphere::calib
