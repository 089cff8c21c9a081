// SPDX-License-Identifier: MIT
/// @brief SourceImage: construction and the double-precision bilinear sample.
#include "xr/source_image.h"

#include <algorithm>
#include <cmath>

namespace telesphere::xr {
namespace {

/// Bilinear weights and clamped texel indices for normalised coordinate s over n texels.
struct Axis {
  int i0, i1;
  double w;
};

Axis axis(double s, int n) {
  const double f = s * n - 0.5;
  const double fl = std::floor(f);
  const int i = static_cast<int>(fl);
  return {std::clamp(i, 0, n - 1), std::clamp(i + 1, 0, n - 1), f - fl};
}

template <typename Fetch>
double bilinear(double u, double v, int w, int h, const Fetch& fetch) {
  const Axis ax = axis(u, w), ay = axis(v, h);
  const double top = (1 - ax.w) * fetch(ax.i0, ay.i0) + ax.w * fetch(ax.i1, ay.i0);
  const double bottom = (1 - ax.w) * fetch(ax.i0, ay.i1) + ax.w * fetch(ax.i1, ay.i1);
  return (1 - ay.w) * top + ay.w * bottom;
}

}  // namespace

SourceImage SourceImage::rgb8(int width, int height, std::vector<std::uint8_t> rgb) {
  SourceImage s;
  s.format = Format::kRgb8;
  s.width = width;
  s.height = height;
  s.channels = 3;
  s.bytes = std::move(rgb);
  return s;
}

SourceImage SourceImage::floatImage(int width, int height, int channels, std::vector<float> data) {
  SourceImage s;
  s.format = Format::kFloat;
  s.width = width;
  s.height = height;
  s.channels = channels;
  s.floats = std::move(data);
  return s;
}

SourceImage SourceImage::yuv(int width, int height, int chroma_width, int chroma_height,
                             std::vector<std::uint8_t> planes) {
  SourceImage s;
  s.format = Format::kYuv;
  s.width = width;
  s.height = height;
  s.channels = 3;
  s.chroma_width = chroma_width;
  s.chroma_height = chroma_height;
  s.bytes = std::move(planes);
  return s;
}

SourceImage SourceImage::pixelCoordinates(int width, int height) {
  std::vector<float> data(static_cast<std::size_t>(width) * height * 2);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 2;
      data[i] = static_cast<float>(x);
      data[i + 1] = static_cast<float>(y);
    }
  return floatImage(width, height, 2, std::move(data));
}

bool SourceImage::consistent() const {
  if (width <= 0 || height <= 0) return false;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  switch (format) {
    case Format::kRgb8: return channels == 3 && bytes.size() == n * 3;
    case Format::kFloat:
      return channels >= 1 && channels <= 4 && floats.size() == n * static_cast<std::size_t>(channels);
    case Format::kYuv:
      return chroma_width > 0 && chroma_height > 0 && chroma_width <= width &&
             chroma_height <= height &&
             bytes.size() == n + 2 * static_cast<std::size_t>(chroma_width) * chroma_height;
  }
  return false;
}

Eigen::Vector4d SourceImage::sample(const Eigen::Vector2d& px) const {
  const double u = (px.x() + 0.5) / width, v = (px.y() + 0.5) / height;
  Eigen::Vector4d out(0, 0, 0, 1);
  switch (format) {
    case Format::kRgb8:
      for (int c = 0; c < 3; ++c)
        out[c] = bilinear(u, v, width, height, [&](int x, int y) {
          return bytes[(static_cast<std::size_t>(y) * width + x) * 3 + c] / 255.0;
        });
      break;
    case Format::kFloat:
      for (int c = 0; c < channels; ++c)
        out[c] = bilinear(u, v, width, height, [&](int x, int y) {
          return double(floats[(static_cast<std::size_t>(y) * width + x) * channels + c]);
        });
      break;
    case Format::kYuv: {
      const std::size_t n = static_cast<std::size_t>(width) * height;
      const std::size_t nc = static_cast<std::size_t>(chroma_width) * chroma_height;
      const double Y = bilinear(u, v, width, height, [&](int x, int y) {
        return bytes[static_cast<std::size_t>(y) * width + x] / 255.0;
      });
      const auto chroma = [&](std::size_t offset) {
        return bilinear(u, v, chroma_width, chroma_height, [&](int x, int y) {
                 return bytes[offset + static_cast<std::size_t>(y) * chroma_width + x] / 255.0;
               }) -
               128.0 / 255.0;
      };
      const double cb = chroma(n), cr = chroma(n + nc);
      out.head<3>() << Y + 1.402 * cr, Y - 0.344136 * cb - 0.714136 * cr, Y + 1.772 * cb;
      out.head<3>() = out.head<3>().cwiseMax(0.0).cwiseMin(1.0);
      break;
    }
  }
  return out;
}

}  // namespace telesphere::xr
