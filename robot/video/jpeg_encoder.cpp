// SPDX-License-Identifier: MIT
/// @brief JpegEncoder over libjpeg-turbo's libjpeg API (jpeglib.h): TurboJPEG 2.1's tjCompress2
///        cannot place restart markers, and the Internet link slices frames along them.
///        libjpeg reports errors through a callback that must not return; it long-jumps back
///        into encode(), which holds no object with a destructor between setjmp and the jump.
#include "robot/video/jpeg_encoder.h"

// jpeglib.h needs size_t and FILE declared before it.
#include <cstddef>
#include <cstdio>
#include <csetjmp>
#include <jpeglib.h>

#include <stdexcept>

namespace telesphere::robot::video {

struct JpegEncoder::Compressor {
  struct ErrorManager {
    jpeg_error_mgr pub;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
  };
  /// Writes into a std::vector that grows by doubling when libjpeg fills it.
  struct Destination {
    jpeg_destination_mgr pub;
    std::vector<std::uint8_t>* out = nullptr;
  };

  jpeg_compress_struct cinfo{};
  ErrorManager error{};
  Destination destination{};

  Compressor() {
    cinfo.err = jpeg_std_error(&error.pub);
    error.pub.error_exit = &onError;
    error.pub.output_message = [](j_common_ptr) {};  // warnings: none matter to an encoder
    jpeg_create_compress(&cinfo);
    destination.pub.init_destination = &initDestination;
    destination.pub.empty_output_buffer = &emptyOutputBuffer;
    destination.pub.term_destination = &termDestination;
    cinfo.dest = &destination.pub;
  }
  ~Compressor() { jpeg_destroy_compress(&cinfo); }

  [[noreturn]] static void onError(j_common_ptr common) {
    auto* manager = reinterpret_cast<ErrorManager*>(common->err);
    (*common->err->format_message)(common, manager->message);
    std::longjmp(manager->jump, 1);
  }
  static Destination& destinationOf(j_compress_ptr c) { return *reinterpret_cast<Destination*>(c->dest); }
  static void initDestination(j_compress_ptr c) {
    auto& d = destinationOf(c);
    d.pub.next_output_byte = d.out->data();
    d.pub.free_in_buffer = d.out->size();
  }
  static boolean emptyOutputBuffer(j_compress_ptr c) {
    // libjpeg calls this when the whole buffer is full (free_in_buffer is 0).
    auto& d = destinationOf(c);
    const std::size_t used = d.out->size();
    d.out->resize(used * 2);
    d.pub.next_output_byte = d.out->data() + used;
    d.pub.free_in_buffer = d.out->size() - used;
    return TRUE;
  }
  static void termDestination(j_compress_ptr c) {
    auto& d = destinationOf(c);
    d.out->resize(d.out->size() - d.pub.free_in_buffer);
  }
};

JpegEncoder::JpegEncoder() : compressor_(std::make_unique<Compressor>()) {}

JpegEncoder::~JpegEncoder() = default;

bool JpegEncoder::encodeRgb(const std::uint8_t* rgb, int width, int height, int stride,
                            const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
                            std::string* error) {
  return encode(rgb, width, height, stride, 3, settings, out_jpeg, error);
}

bool JpegEncoder::encodeGray(const std::uint8_t* gray, int width, int height, int stride,
                             const JpegSettings& settings, std::vector<std::uint8_t>& out_jpeg,
                             std::string* error) {
  return encode(gray, width, height, stride, 1, settings, out_jpeg, error);
}

bool JpegEncoder::encode(const std::uint8_t* pixels, int width, int height, int stride,
                         int channels, const JpegSettings& settings,
                         std::vector<std::uint8_t>& out_jpeg, std::string* error) {
  if (width <= 0 || height <= 0 || width > 65500 || height > 65500 ||
      stride < channels * width) {
    *error = "bad image size " + std::to_string(width) + "x" + std::to_string(height) +
             " with stride " + std::to_string(stride);
    return false;
  }
  if (settings.quality < 1 || settings.quality > 100) {
    *error = "JPEG quality " + std::to_string(settings.quality) + " is outside 1..100";
    return false;
  }
  if (settings.restart_mcu_rows < 0 || settings.restart_mcu_rows > 65535) {
    *error = "JPEG restart interval of " + std::to_string(settings.restart_mcu_rows) +
             " MCU rows is outside 0..65535";
    return false;
  }
  // A first guess that fits most frames (q90 4:2:0 is about 0.3 bytes per pixel and channel);
  // the destination doubles it when it does not.
  out_jpeg.resize(static_cast<std::size_t>(width) * height * channels / 2 + 4096);
  const bool gray_out = channels == 1 || settings.subsampling == ChromaSubsampling::kGray;
  int h_samp = 1, v_samp = 1;
  if (!gray_out && settings.subsampling == ChromaSubsampling::k420) h_samp = v_samp = 2;
  if (!gray_out && settings.subsampling == ChromaSubsampling::k422) h_samp = 2;

  Compressor& c = *compressor_;
  jpeg_compress_struct& cinfo = c.cinfo;
  c.destination.out = &out_jpeg;
  if (setjmp(c.error.jump) != 0) {
    jpeg_abort_compress(&cinfo);
    *error = std::string("libjpeg: ") + c.error.message;
    return false;
  }
  cinfo.image_width = static_cast<JDIMENSION>(width);
  cinfo.image_height = static_cast<JDIMENSION>(height);
  cinfo.input_components = channels;
  cinfo.in_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&cinfo);
  if (gray_out) jpeg_set_colorspace(&cinfo, JCS_GRAYSCALE);
  jpeg_set_quality(&cinfo, settings.quality, TRUE);
  if (!gray_out) {
    cinfo.comp_info[0].h_samp_factor = h_samp;
    cinfo.comp_info[0].v_samp_factor = v_samp;
    for (int k = 1; k < 3; ++k) cinfo.comp_info[k].h_samp_factor = cinfo.comp_info[k].v_samp_factor = 1;
  }
  // As TurboJPEG with TJFLAG_FASTDCT did: the fast integer DCT, except at the qualities where
  // its rounding shows.
  cinfo.dct_method = settings.quality >= 96 ? JDCT_ISLOW : JDCT_IFAST;
  cinfo.restart_interval = 0;
  cinfo.restart_in_rows = settings.restart_mcu_rows;
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    // Up to 32 rows per call, straight from the caller's memory.
    JSAMPROW rows[32];
    JDIMENSION n = 0;
    for (; n < 32 && cinfo.next_scanline + n < cinfo.image_height; ++n)
      rows[n] = const_cast<JSAMPROW>(pixels + static_cast<std::size_t>(cinfo.next_scanline + n) * stride);
    jpeg_write_scanlines(&cinfo, rows, n);
  }
  jpeg_finish_compress(&cinfo);
  return true;
}

}  // namespace telesphere::robot::video
