// SPDX-License-Identifier: MIT
/// @brief JpegDecoder over tjDecompressHeader3 + tjDecompressToYUVPlanes.
#include "xr/video/jpeg_decoder.h"

#include <turbojpeg.h>

#include <stdexcept>

namespace telesphere::xr::video {

JpegDecoder::JpegDecoder() : handle_(tjInitDecompress()) {
  if (!handle_) throw std::runtime_error(std::string("tjInitDecompress: ") + tjGetErrorStr2(nullptr));
}

JpegDecoder::~JpegDecoder() { tjDestroy(handle_); }

const char* jpegDecodeErrorName(JpegDecodeError error) {
  switch (error) {
    case JpegDecodeError::kNone: return "none";
    case JpegDecodeError::kCorrupt: return "corrupt";
    case JpegDecodeError::kTooLarge: return "too_large";
    case JpegDecodeError::kSizeMismatch: return "size_mismatch";
    case JpegDecodeError::kUnsupported: return "unsupported";
  }
  return "unknown";
}

JpegDecodeError JpegDecoder::readHeader(std::span<const std::uint8_t> jpeg, int expected_width,
                                        int expected_height, int max_side, JpegHeader* out, std::string* error) {
  int width = 0, height = 0, subsamp = 0, colorspace = 0;
  if (jpeg.empty() ||
      tjDecompressHeader3(handle_, jpeg.data(), static_cast<unsigned long>(jpeg.size()), &width,
                          &height, &subsamp, &colorspace) != 0) {
    *error = std::string("JPEG header: ") + tjGetErrorStr2(handle_);
    return JpegDecodeError::kCorrupt;
  }
  if (width <= 0 || height <= 0 || width > max_side || height > max_side) {
    *error = "JPEG of " + std::to_string(width) + "x" + std::to_string(height) +
             " exceeds the limit of " + std::to_string(max_side) + " px per side";
    return JpegDecodeError::kTooLarge;
  }
  if ((expected_width > 0 && width != expected_width) || (expected_height > 0 && height != expected_height)) {
    *error = "JPEG is " + std::to_string(width) + "x" + std::to_string(height) + ", the message said " +
             std::to_string(expected_width) + "x" + std::to_string(expected_height);
    return JpegDecodeError::kSizeMismatch;
  }
  switch (subsamp) {
    case TJSAMP_420: out->subsampling = link::ChromaSubsampling::k420; break;
    case TJSAMP_422: out->subsampling = link::ChromaSubsampling::k422; break;
    case TJSAMP_444: out->subsampling = link::ChromaSubsampling::k444; break;
    case TJSAMP_GRAY: out->subsampling = link::ChromaSubsampling::kGray; break;
    default:
      *error = "JPEG chroma subsampling " + std::to_string(subsamp) + " is not one the renderer takes";
      return JpegDecodeError::kUnsupported;
  }
  const bool gray = subsamp == TJSAMP_GRAY;
  out->layout = {width, height, gray ? 0 : tjPlaneWidth(1, width, subsamp), gray ? 0 : tjPlaneHeight(1, height, subsamp)};
  return JpegDecodeError::kNone;
}

JpegDecodeError JpegDecoder::decodeInto(std::span<const std::uint8_t> jpeg, const JpegHeader& header,
                                        std::uint8_t* y, std::uint8_t* u, std::uint8_t* v, std::string* error) {
  const render::PlaneLayout& l = header.layout;
  const bool gray = header.subsampling == link::ChromaSubsampling::kGray;
  unsigned char* planes[3] = {y, gray ? nullptr : u, gray ? nullptr : v};
  int strides[3] = {l.width, l.chroma_width, l.chroma_width};
  if (tjDecompressToYUVPlanes(handle_, jpeg.data(), static_cast<unsigned long>(jpeg.size()), planes,
                              l.width, strides, l.height, TJFLAG_FASTDCT | TJFLAG_STOPONWARNING) != 0) {
    // Warnings too (a truncated file decodes half grey): the operator keeps the previous frame
    // rather than seeing a broken one.
    *error = std::string("JPEG data: ") + tjGetErrorStr2(handle_);
    return JpegDecodeError::kCorrupt;
  }
  return JpegDecodeError::kNone;
}

JpegDecodeError JpegDecoder::decode(std::span<const std::uint8_t> jpeg, int expected_width,
                                    int expected_height, int max_side, render::YuvPlanes& out,
                                    std::string* error) {
  JpegHeader header;
  if (const auto e = readHeader(jpeg, expected_width, expected_height, max_side, &header, error);
      e != JpegDecodeError::kNone)
    return e;
  out.subsampling = header.subsampling;
  out.width = header.layout.width;
  out.height = header.layout.height;
  out.chroma_width = header.layout.chroma_width;
  out.chroma_height = header.layout.chroma_height;
  out.slot.reset();
  out.y.resize(header.layout.lumaBytes());
  out.u.resize(header.layout.chromaBytes());
  out.v.resize(out.u.size());
  return decodeInto(jpeg, header, out.y.data(), out.u.data(), out.v.data(), error);
}

}  // namespace telesphere::xr::video
