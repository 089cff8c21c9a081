// SPDX-License-Identifier: MIT
/// @brief SourceImage: construction and the double-precision bilinear sample.
#include "xr/render/source_image.h"

#include <algorithm>
#include <cmath>

namespace telesphere::xr::render {
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

SourceImage SourceImage::yuv(std::shared_ptr<const YuvPlanes> planes) {
  SourceImage s;
  s.format = Format::kYuv;
  s.channels = 3;
  if (planes) {
    s.width = planes->width;
    s.height = planes->height;
    s.chroma_width = planes->chroma_width;
    s.chroma_height = planes->chroma_height;
  }
  s.planes = std::move(planes);
  return s;
}

SourceImage SourceImage::yuv(int width, int height, int chroma_width, int chroma_height,
                             const std::vector<std::uint8_t>& concatenated) {
  auto p = std::make_shared<YuvPlanes>();
  p->width = width;
  p->height = height;
  p->chroma_width = chroma_width;
  p->chroma_height = chroma_height;
  p->subsampling = std::nullopt;
  const std::size_t n = width > 0 && height > 0 ? static_cast<std::size_t>(width) * height : 0;
  const std::size_t nc = chroma_width > 0 && chroma_height > 0
                             ? static_cast<std::size_t>(chroma_width) * chroma_height
                             : 0;
  if (n > 0 && nc > 0 && concatenated.size() == n + 2 * nc) {
    const auto begin = concatenated.begin();
    p->y.assign(begin, begin + static_cast<std::ptrdiff_t>(n));
    p->u.assign(begin + static_cast<std::ptrdiff_t>(n), begin + static_cast<std::ptrdiff_t>(n + nc));
    p->v.assign(begin + static_cast<std::ptrdiff_t>(n + nc), concatenated.end());
  } else {
    p->y = concatenated;  // wrong size: kept whole, so that consistent() says no
  }
  SourceImage s = yuv(std::shared_ptr<const YuvPlanes>(std::move(p)));
  // The sizes the caller claimed, even when the buffer disagrees with them.
  s.width = width;
  s.height = height;
  s.chroma_width = chroma_width;
  s.chroma_height = chroma_height;
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
    case Format::kYuv: {
      if (!planes || planes->width != width || planes->height != height ||
          planes->chroma_width != chroma_width || planes->chroma_height != chroma_height)
        return false;
      if (chroma_width == 0 && chroma_height == 0)  // greyscale: Y only
        return planes->yPlane().size() == n && planes->uPlane().empty() && planes->vPlane().empty();
      const std::size_t nc = static_cast<std::size_t>(chroma_width) * chroma_height;
      return chroma_width > 0 && chroma_height > 0 && chroma_width <= width &&
             chroma_height <= height && planes->yPlane().size() == n && planes->uPlane().size() == nc &&
             planes->vPlane().size() == nc;
    }
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
      const std::span<const std::uint8_t> luma = planes->yPlane();
      const double Y = bilinear(u, v, width, height, [&](int x, int y) {
        return luma[static_cast<std::size_t>(y) * width + x] / 255.0;
      });
      const auto chroma = [&](std::span<const std::uint8_t> plane) {
        return bilinear(u, v, chroma_width, chroma_height, [&](int x, int y) {
                 return plane[static_cast<std::size_t>(y) * chroma_width + x] / 255.0;
               }) -
               128.0 / 255.0;
      };
      const bool grey = chroma_width == 0;
      const double cb = grey ? 0.0 : chroma(planes->uPlane()), cr = grey ? 0.0 : chroma(planes->vPlane());
      out.head<3>() << Y + 1.402 * cr, Y - 0.344136 * cb - 0.714136 * cr, Y + 1.772 * cb;
      out.head<3>() = out.head<3>().cwiseMax(0.0).cwiseMin(1.0);
      break;
    }
  }
  return out;
}

}  // namespace telesphere::xr::render
