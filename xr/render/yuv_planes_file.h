// SPDX-License-Identifier: MIT
/// @brief YuvPlanes to and from a file, byte for byte: a one-line text header
///        "telesphere-yuv WIDTH HEIGHT CHROMA_WIDTH CHROMA_HEIGHT SUBSAMPLING\n" then the Y, U and V
///        planes; SUBSAMPLING is 0 4:2:0, 1 4:2:2, 2 4:4:4, 3 grey, 4 not from a JPEG. The operator app saves the decoded camera images it showed (readback mode), so a
///        test can render the very same planes again and compare.
#pragma once

#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "xr/render/yuv_planes.h"

namespace telesphere::xr::render {

/// The header's SUBSAMPLING for planes not from a JPEG.
inline constexpr int kNotFromJpeg = 4;

inline bool writeYuvPlanes(const std::string& path, const YuvPlanes& planes, std::string* error) {
  std::ofstream out(path, std::ios::binary);
  out << "telesphere-yuv " << planes.width << ' ' << planes.height << ' ' << planes.chroma_width << ' '
      << planes.chroma_height << ' ' << (planes.subsampling ? static_cast<int>(*planes.subsampling) : kNotFromJpeg)
      << '\n';
  for (const auto plane : {planes.yPlane(), planes.uPlane(), planes.vPlane()})
    out.write(reinterpret_cast<const char*>(plane.data()), static_cast<std::streamsize>(plane.size()));
  if (!out) {
    *error = path + ": cannot write the YUV planes";
    return false;
  }
  return true;
}

inline std::optional<YuvPlanes> readYuvPlanes(const std::string& path, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  std::string header, magic;
  if (!in || !std::getline(in, header)) {
    *error = path + ": cannot read";
    return std::nullopt;
  }
  std::istringstream h(header);
  YuvPlanes planes;
  int subsampling = -1;
  if (!(h >> magic >> planes.width >> planes.height >> planes.chroma_width >> planes.chroma_height >> subsampling) ||
      magic != "telesphere-yuv" || planes.width <= 0 || planes.height <= 0 || planes.width > 16384 ||
      planes.height > 16384 || planes.chroma_width < 0 || planes.chroma_height < 0 ||
      planes.chroma_width > planes.width || planes.chroma_height > planes.height || subsampling < 0 ||
      subsampling > kNotFromJpeg) {
    *error = path + ": not a telesphere-yuv file (header \"" + header + "\")";
    return std::nullopt;
  }
  planes.subsampling = subsampling == kNotFromJpeg ? std::nullopt
                                                   : std::optional(static_cast<link::ChromaSubsampling>(subsampling));
  planes.y.resize(std::size_t(planes.width) * std::size_t(planes.height));
  const std::size_t chroma = planes.subsampling == link::ChromaSubsampling::kGray
                                 ? 0 : std::size_t(planes.chroma_width) * std::size_t(planes.chroma_height);
  planes.u.resize(chroma);
  planes.v.resize(chroma);
  for (auto* p : {&planes.y, &planes.u, &planes.v})
    in.read(reinterpret_cast<char*>(p->data()), static_cast<std::streamsize>(p->size()));
  if (!in) {
    *error = path + ": truncated YUV planes";
    return std::nullopt;
  }
  return planes;
}

}  // namespace telesphere::xr::render
