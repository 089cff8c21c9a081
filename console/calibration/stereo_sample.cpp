// SPDX-License-Identifier: MIT
/// @brief StereoSample (see stereo_sample.h).
#include "console/calibration/stereo_sample.h"

#include <algorithm>

namespace telesphere::console::calibration {

calib::GrayImage grayImageOf(const link::proto::CalibrationImage& image) {
  const std::size_t n = std::size_t(image.width()) * std::size_t(image.height());
  if (n == 0 || image.gray8().size() != n) return {};
  calib::GrayImage out;
  out.width = int(image.width());
  out.height = int(image.height());
  out.pixels.assign(image.gray8().begin(), image.gray8().end());
  return out;
}

calib::GrayImage thumbnailOf(const calib::GrayImage& image, int max_width) {
  if (image.width <= 0 || image.height <= 0) return {};
  const int f = std::max(1, (image.width + max_width - 1) / max_width);
  calib::GrayImage out(image.width / f, image.height / f);
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u) {
      int sum = 0;
      for (int dv = 0; dv < f; ++dv)
        for (int du = 0; du < f; ++du) sum += image.at(u * f + du, v * f + dv);
      out.at(u, v) = static_cast<std::uint8_t>(sum / (f * f));
    }
  return out;
}

StereoSample detectStereoSample(const link::proto::CalibrationStill& still, const calib::AprilGrid& grid,
                                const calib::DetectionOptions& options, int thumbnail_width) {
  StereoSample sample;
  sample.sequence = still.sequence();
  sample.capture_ns = still.capture_ns();
  sample.head_joints.assign(still.head_joints().begin(), still.head_joints().end());
  const link::proto::CalibrationImage* images[2] = {&still.left(), &still.right()};
  for (int c = 0; c < 2; ++c) {
    const calib::GrayImage image = grayImageOf(*images[c]);
    if (image.pixels.empty()) continue;
    sample.width = image.width;
    sample.height = image.height;
    sample.views[std::size_t(c)] = calib::detectAprilGrid(image, grid, options);
    sample.thumbnails[std::size_t(c)] = thumbnailOf(image, thumbnail_width);
  }
  return sample;
}

}  // namespace telesphere::console::calibration
