// SPDX-License-Identifier: MIT
/// @brief OpenXrTestScene: the camera model, the checkerboard image and the yaw-only nominal.
#include "xr/openxr/openxr_test_scene.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>


namespace telesphere::xr::openxr {

calib::GenericCamera OpenXrTestScene::camera() {
  // The simulated head's lens (calib/data/sim_calibration.yaml) at a quarter of 3840×2160.
  Eigen::VectorXd params(6);
  params << 232.5, 232.5, 479.5, 269.5, -0.18, 0.59;  // fx fy cx cy xi alpha
  auto camera = calib::GenericCamera::create("ds", params);
  if (!camera) std::abort();  // constant parameters inside the model's domain
  return *camera;
}

render::SourceImage OpenXrTestScene::image() {
  constexpr int w = kImageWidth, h = kImageHeight, square = 40;
  std::vector<std::uint8_t> rgb(std::size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = (std::size_t(y) * w + std::size_t(x)) * 3;
      const bool odd = ((x / square) + (y / square)) % 2 == 1;
      const bool cross = (std::abs(x - w / 2) <= 2 && std::abs(y - h / 2) <= 60) ||
                         (std::abs(y - h / 2) <= 2 && std::abs(x - w / 2) <= 60);
      rgb[i] = cross ? 255 : std::uint8_t(x * 255 / (w - 1));
      rgb[i + 1] = cross ? 255 : std::uint8_t(y * 255 / (h - 1));
      rgb[i + 2] = cross ? 255 : (odd ? 192 : 64);
    }
  return render::SourceImage::rgb8(w, h, std::move(rgb));
}

}  // namespace telesphere::xr::openxr
