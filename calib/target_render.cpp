// SPDX-License-Identifier: MIT
/// @brief Synthetic target images (see target_render.h).
#include "calib/target_render.h"

#include <cmath>
#include <memory>
#include <opencv2/aruco.hpp>
#include <random>
#include <vector>

#include "calib/aruco_dictionary.h"

namespace telesphere::calib {
namespace {

/// The code image of marker `id` with `border_bits`, one pixel per bit (0 black, 255 white).
cv::Mat markerBitImage(const cv::Ptr<cv::aruco::Dictionary>& dict, int id, int border_bits) {
  cv::Mat bits;
  cv::aruco::drawMarker(dict, id, dict->markerSize + 2 * border_bits, bits, border_bits);
  return bits;
}

}  // namespace

TargetTexture aprilGridTexture(const AprilGrid& grid, bool corner_squares) {
  const auto dict = detail::arucoDictionary("DICT_APRILTAG_36h11");
  auto tags = std::make_shared<std::vector<cv::Mat>>();
  for (int id = 0; id < grid.numTags(); ++id) tags->push_back(markerBitImage(dict, id, 2));
  const int n_bits = tags->front().cols;  // 10: 6 data bits and 2-bit borders
  return [grid, tags, n_bits, corner_squares](double x, double y) -> int {
    const double s = grid.tag_size, pitch = grid.pitch(), margin = grid.tag_size;
    if (x < -margin || y < -margin || x > grid.width() + margin || y > grid.height() + margin)
      return -1;
    const int col = static_cast<int>(std::floor(x / pitch));
    const int row = static_cast<int>(std::floor(y / pitch));
    const double lx = x - col * pitch, ly = y - row * pitch;
    const bool in_x = col >= 0 && col < grid.tag_cols, in_y = row >= 0 && row < grid.tag_rows;
    if (in_x && in_y && lx < s && ly < s) {
      // Printed rotated by 180°: the code image's u runs along −x, its v (down) along +y.
      const int bu = std::clamp(static_cast<int>((s - lx) / s * n_bits), 0, n_bits - 1);
      const int bv = std::clamp(static_cast<int>(ly / s * n_bits), 0, n_bits - 1);
      return (*tags)[static_cast<std::size_t>(row * grid.tag_cols + col)].at<std::uint8_t>(bv, bu);
    }
    // kalibr's squares where the gaps between tag corners cross (also on the outer border).
    const bool gap_x = lx >= s && col >= -1 && col < grid.tag_cols;
    const bool gap_y = ly >= s && row >= -1 && row < grid.tag_rows;
    if (corner_squares && gap_x && gap_y) return 0;
    return 255;
  };
}

TargetTexture arucoMarkerTexture(const std::string& dictionary, int id, double size) {
  const auto dict = detail::arucoDictionary(dictionary);
  auto bits = std::make_shared<cv::Mat>(markerBitImage(dict, id, 1));
  return [bits, size](double x, double y) -> int {
    const double h = 0.5 * size;
    if (std::abs(x) > 2 * h || std::abs(y) > 2 * h) return -1;
    if (std::abs(x) >= h || std::abs(y) >= h) return 255;
    const int n = bits->cols;
    const int u = std::clamp(static_cast<int>((x + h) / size * n), 0, n - 1);
    const int v = std::clamp(static_cast<int>((h - y) / size * n), 0, n - 1);
    return bits->at<std::uint8_t>(v, u);
  };
}

GrayImage renderTarget(const GenericCamera& camera, int width, int height,
                       const Eigen::Isometry3d& T_cam_target, const TargetTexture& texture,
                       const RenderOptions& options) {
  GrayImage image(width, height, 0);
  const int n = std::max(1, options.supersampling);
  const Eigen::Isometry3d T_target_cam = T_cam_target.inverse();
  const Eigen::Vector3d o_target = T_target_cam.translation();
  const Eigen::Matrix3d R_target_cam = T_target_cam.linear();
  std::mt19937 rng(options.noise_seed);
  std::normal_distribution<double> noise(0.0, options.noise_sigma);
  camera.visit([&](const auto& model) {
    using Model = std::decay_t<decltype(model)>;
    for (int v = 0; v < height; ++v) {
      for (int u = 0; u < width; ++u) {
        double sum = 0.0;
        int valid = 0;
        for (int j = 0; j < n; ++j) {
          for (int i = 0; i < n; ++i) {
            const typename Model::Vec2 px(u + (i + 0.5) / n - 0.5, v + (j + 0.5) / n - 0.5);
            typename Model::Vec3 d_cam;
            if (!model.unproject(px, d_cam)) continue;
            ++valid;
            const Eigen::Vector3d d_target = R_target_cam * d_cam;
            // o + t·d meets z = 0 at t = −o_z/d_z, in front of the camera iff t > 0.
            const double t = -o_target.z() / d_target.z();
            int value = -1;
            if (std::isfinite(t) && t > 0.0) {
              const Eigen::Vector3d p = o_target + t * d_target;
              value = texture(p.x(), p.y());
            }
            sum += value < 0 ? options.background : value;
          }
        }
        if (valid == 0) continue;
        // Sub-samples outside the image region count as black: the rim is anti-aliased too.
        double value = sum / (n * n);
        if (options.noise_sigma > 0.0) value += noise(rng);
        image.at(u, v) = static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
      }
    }
  });
  return image;
}

}  // namespace telesphere::calib
