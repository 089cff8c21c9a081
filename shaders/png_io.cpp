// SPDX-License-Identifier: MIT
/// @brief writePng and readPng with libpng's simplified API.
#include "shaders/png_io.h"

#include <png.h>

#include <cstring>

namespace telesphere::gl {

bool writePng(const std::string& path, int width, int height, int channels,
              const std::uint8_t* pixels, std::string* out_error) {
  if (width <= 0 || height <= 0 || (channels != 3 && channels != 4) || pixels == nullptr) {
    if (out_error) *out_error = path + ": nothing to write (empty image or bad channel count)";
    return false;
  }
  png_image image;
  std::memset(&image, 0, sizeof(image));
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = channels == 4 ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  if (!png_image_write_to_file(&image, path.c_str(), 0, pixels, 0, nullptr)) {
    if (out_error) *out_error = path + ": cannot write PNG: " + image.message;
    png_image_free(&image);
    return false;
  }
  return true;
}

std::optional<PngImage> readPng(const std::string& path, std::string* out_error) {
  png_image image;
  std::memset(&image, 0, sizeof(image));
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    if (out_error) *out_error = path + ": cannot read PNG: " + image.message;
    png_image_free(&image);
    return std::nullopt;
  }
  image.format = PNG_FORMAT_RGBA;
  PngImage out;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.rgba.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out.rgba.data(), 0, nullptr)) {
    if (out_error) *out_error = path + ": cannot decode PNG: " + image.message;
    png_image_free(&image);
    return std::nullopt;
  }
  return out;
}

}  // namespace telesphere::gl
