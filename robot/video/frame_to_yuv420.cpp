// SPDX-License-Identifier: MIT
/// @brief FrameToYuv420: Bayer, RGB and grey camera images into YUV 4:2:0 planes.
#include "robot/video/frame_to_yuv420.h"

#include <turbojpeg.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "robot/cameras/debayer_yuv420.h"

namespace telesphere::robot::video {

struct FrameToYuv420::Impl {
  tjhandle rgb = nullptr;  ///< TurboJPEG's RGB → YCbCr (made on the first RGB image)
  cameras::DebayerToYuv420 debayer;
  std::vector<std::uint8_t> padded_y;  ///< TurboJPEG's Y plane of an odd-sized image (scratch)
  ~Impl() {
    if (rgb) tjDestroy(rgb);
  }
};

FrameToYuv420::FrameToYuv420() : impl_(std::make_unique<Impl>()) {}
FrameToYuv420::~FrameToYuv420() = default;

bool FrameToYuv420::convert(const cameras::CameraFrame& frame, cameras::Yuv420Image& out, std::string* error) {
  const int bpp = cameras::bytesPerPixel(frame.format);
  if (frame.width < 2 || frame.height < 2 || frame.stride_bytes < frame.width * bpp || !frame.pixels ||
      frame.pixels->size() < static_cast<std::size_t>(frame.stride_bytes) * (frame.height - 1) +
                                 static_cast<std::size_t>(frame.width) * bpp) {
    *error = std::string("a ") + cameras::pixelFormatName(frame.format) + " image of " + std::to_string(frame.width) +
             "x" + std::to_string(frame.height) + " px, rows " + std::to_string(frame.stride_bytes) +
             " bytes apart, does not hold its pixels (" + std::to_string(frame.pixels ? frame.pixels->size() : 0) +
             " bytes)";
    return false;
  }
  const std::uint8_t* src = frame.pixels->data();
  switch (frame.format) {
    case cameras::PixelFormat::kMono8:
      out.resize(frame.width, frame.height);
      for (int row = 0; row < frame.height; ++row)
        std::memcpy(out.y.data() + static_cast<std::size_t>(row) * frame.width,
                    src + static_cast<std::size_t>(row) * frame.stride_bytes, static_cast<std::size_t>(frame.width));
      std::fill(out.u.begin(), out.u.end(), std::uint8_t{128});
      std::fill(out.v.begin(), out.v.end(), std::uint8_t{128});
      return true;
    case cameras::PixelFormat::kRgb8: {
      if (!impl_->rgb && !(impl_->rgb = tjInitCompress())) {
        *error = std::string("TurboJPEG: ") + tjGetErrorStr2(nullptr);
        return false;
      }
      out.resize(frame.width, frame.height);
      // TurboJPEG writes the Y plane of an odd-sized image padded to even width and height (one
      // more column and row than ours): there it writes into scratch rows, copied over after.
      const int y_width = tjPlaneWidth(0, frame.width, TJSAMP_420);
      const int y_height = tjPlaneHeight(0, frame.height, TJSAMP_420);
      const bool padded = y_width != frame.width || y_height != frame.height;
      if (padded) impl_->padded_y.resize(static_cast<std::size_t>(y_width) * y_height);
      unsigned char* planes[3] = {padded ? impl_->padded_y.data() : out.y.data(), out.u.data(), out.v.data()};
      int strides[3] = {padded ? y_width : frame.width, out.chromaWidth(), out.chromaWidth()};
      if (tjEncodeYUVPlanes(impl_->rgb, src, frame.width, frame.stride_bytes, frame.height, TJPF_RGB, planes, strides,
                            TJSAMP_420, 0) != 0) {
        *error = std::string("TurboJPEG RGB → YUV: ") + tjGetErrorStr2(impl_->rgb);
        return false;
      }
      if (padded)
        for (int row = 0; row < frame.height; ++row)
          std::memcpy(out.y.data() + static_cast<std::size_t>(row) * frame.width,
                      impl_->padded_y.data() + static_cast<std::size_t>(row) * y_width, static_cast<std::size_t>(frame.width));
      return true;
    }
    case cameras::PixelFormat::kBayerRG8:
    case cameras::PixelFormat::kBayerGR8:
    case cameras::PixelFormat::kBayerGB8:
    case cameras::PixelFormat::kBayerBG8:
      return impl_->debayer.convert(src, frame.width, frame.height, frame.stride_bytes, frame.format, out, error);
  }
  *error = "an unknown pixel format";
  return false;
}

}  // namespace telesphere::robot::video
