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

#include <algorithm>
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
  /// encodeYuv420's rows padded to whole blocks (16 Y rows, 8 Cb and 8 Cr of one MCU row) when
  /// the width is not a multiple of 16; kept between frames.
  std::vector<std::uint8_t> padded_rows;

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

  /// One image's parameters, from libjpeg's defaults on. Call after the caller's setjmp: a libjpeg
  /// error long-jumps back there (nothing here has a destructor to skip).
  void configure(int width, int height, int components, J_COLOR_SPACE in_color_space, bool gray_out, int h_samp,
                 int v_samp, const JpegSettings& settings) {
    cinfo.image_width = static_cast<JDIMENSION>(width);
    cinfo.image_height = static_cast<JDIMENSION>(height);
    cinfo.input_components = components;
    cinfo.in_color_space = in_color_space;
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
  }

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

bool JpegEncoder::checkInput(int width, int height, const JpegSettings& settings, std::string* error) {
  if (width <= 0 || height <= 0 || width > 65500 || height > 65500) {
    *error = "bad image size " + std::to_string(width) + "x" + std::to_string(height);
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
  return true;
}

bool JpegEncoder::encode(const std::uint8_t* pixels, int width, int height, int stride,
                         int channels, const JpegSettings& settings,
                         std::vector<std::uint8_t>& out_jpeg, std::string* error) {
  if (stride < channels * width) {
    *error = "bad image size " + std::to_string(width) + "x" + std::to_string(height) +
             " with stride " + std::to_string(stride);
    return false;
  }
  if (!checkInput(width, height, settings, error)) return false;
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
  c.configure(width, height, channels, channels == 1 ? JCS_GRAYSCALE : JCS_RGB, gray_out, h_samp, v_samp, settings);
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

bool JpegEncoder::encodeYuv420(const cameras::Yuv420Image& image, const JpegSettings& settings,
                               std::vector<std::uint8_t>& out_jpeg, std::string* error) {
  const int width = image.width, height = image.height;
  if (!checkInput(width, height, settings, error)) return false;
  const bool gray_out = settings.subsampling == ChromaSubsampling::kGray;
  if (!gray_out && settings.subsampling != ChromaSubsampling::k420) {
    *error = std::string("YUV 4:2:0 planes cannot make a ") +
             (settings.subsampling == ChromaSubsampling::k444 ? "4:4:4" : "4:2:2") +
             " JPEG (their chroma has a quarter of the pixels): encode an RGB image, or ask for 4:2:0";
    return false;
  }
  const int chroma_width = image.chromaWidth(), chroma_height = image.chromaHeight();
  const std::size_t luma_size = static_cast<std::size_t>(width) * height;
  const std::size_t chroma_size = static_cast<std::size_t>(chroma_width) * chroma_height;
  if (image.y.size() < luma_size || (!gray_out && (image.u.size() < chroma_size || image.v.size() < chroma_size))) {
    *error = "YUV planes hold " + std::to_string(image.y.size()) + "/" + std::to_string(image.u.size()) + "/" +
             std::to_string(image.v.size()) + " bytes, fewer than a " + std::to_string(width) + "x" +
             std::to_string(height) + " image needs";
    return false;
  }
  // An MCU row: 16 Y rows and 8 of each chroma at 4:2:0 (8 Y rows in gray). libjpeg's DCT reads
  // whole blocks, so rows narrower than the MCU grid are copied into padded rows first.
  const int lines = gray_out ? 8 : 16;
  const int luma_padded = (width + 15) / 16 * 16, chroma_padded = (chroma_width + 7) / 8 * 8;
  const bool pad_columns = luma_padded != width;
  Compressor& c = *compressor_;
  if (pad_columns) c.padded_rows.resize(static_cast<std::size_t>(lines) * luma_padded + 16 * chroma_padded);
  out_jpeg.resize(luma_size * 3 / 4 + 4096);  // first guess, as encode()'s

  jpeg_compress_struct& cinfo = c.cinfo;
  c.destination.out = &out_jpeg;
  if (setjmp(c.error.jump) != 0) {
    jpeg_abort_compress(&cinfo);
    *error = std::string("libjpeg: ") + c.error.message;
    return false;
  }
  c.configure(width, height, gray_out ? 1 : 3, gray_out ? JCS_GRAYSCALE : JCS_YCbCr, gray_out, 2, 2, settings);
  cinfo.raw_data_in = TRUE;  // the planes as they are: no colour conversion, no downsampling
#if JPEG_LIB_VERSION >= 70
  cinfo.do_fancy_downsampling = FALSE;
#endif
  jpeg_start_compress(&cinfo, TRUE);

  // Row r of a plane (rows past the end repeat the last, as libjpeg pads an image), padded into
  // `slot` of the scratch rows when the width needs it.
  const auto row = [&](const std::uint8_t* plane, int plane_width, int plane_height, int r, int padded_width,
                       std::uint8_t* slot) -> JSAMPROW {
    const std::uint8_t* source = plane + static_cast<std::size_t>(std::min(r, plane_height - 1)) * plane_width;
    if (!pad_columns) return const_cast<JSAMPROW>(source);
    std::copy_n(source, plane_width, slot);
    std::fill(slot + plane_width, slot + padded_width, source[plane_width - 1]);
    return slot;
  };
  JSAMPROW y_rows[16], cb_rows[8], cr_rows[8];
  JSAMPARRAY planes[3] = {y_rows, cb_rows, cr_rows};
  std::uint8_t* const scratch_y = c.padded_rows.data();
  std::uint8_t* const scratch_cb = scratch_y + static_cast<std::size_t>(lines) * luma_padded;
  std::uint8_t* const scratch_cr = scratch_cb + static_cast<std::size_t>(8) * chroma_padded;
  while (cinfo.next_scanline < cinfo.image_height) {
    const int y0 = static_cast<int>(cinfo.next_scanline);
    for (int i = 0; i < lines; ++i)
      y_rows[i] = row(image.y.data(), width, height, y0 + i, luma_padded,
                      scratch_y + static_cast<std::size_t>(i) * luma_padded);
    if (!gray_out) {
      for (int i = 0; i < 8; ++i) {
        const std::size_t at = static_cast<std::size_t>(i) * chroma_padded;
        cb_rows[i] = row(image.u.data(), chroma_width, chroma_height, y0 / 2 + i, chroma_padded, scratch_cb + at);
        cr_rows[i] = row(image.v.data(), chroma_width, chroma_height, y0 / 2 + i, chroma_padded, scratch_cr + at);
      }
    }
    jpeg_write_raw_data(&cinfo, planes, static_cast<JDIMENSION>(lines));
  }
  jpeg_finish_compress(&cinfo);
  return true;
}

}  // namespace telesphere::robot::video
