// SPDX-License-Identifier: MIT
/// @brief Sensor samples wider than 8 bits narrowed to the 8 bits the video path takes, at capture
///        (#34): GenICam's unpacked Mono10/12/16 and BayerXX10/12/16 hold each sample in the low
///        `sample_bits` bits of a little-endian 16-bit word. JPEG and 8-bit H.264/HEVC keep 8 bits
///        anyway, so one pass at capture lets every later stage (debayer, scaler, encoders) stay
///        8-bit. Packed layouts (Mono12p, BayerRG10p, …) are not handled: the camera is asked for an
///        unpacked one.
#pragma once

#include <cstdint>
#include <string>

namespace telesphere::robot::cameras {

/// Bits per sample narrowSamplesTo8Bits accepts: 9 to 16.
constexpr int kMinWideSampleBits = 9;
constexpr int kMaxWideSampleBits = 16;

/// The 8-bit value of one `sample_bits`-bit sample v: round(v · 255 / (2^sample_bits − 1)), halves
/// up; v above 2^sample_bits − 1 (bits a camera should leave clear) gives 255. The definition the
/// fast path below must equal (tests check every value).
std::uint8_t narrowSampleTo8Bits(std::uint16_t v, int sample_bits);

/// Narrows a width × height image of 16-bit little-endian words (rows `src_stride_bytes` apart, at
/// least 2 · width) into 8-bit samples (rows `dst_stride_bytes` apart, at least width), value by
/// value as narrowSampleTo8Bits. False with "narrowSamplesTo8Bits: <reason>" in *error (when given)
/// for sample_bits outside 9–16, an empty image, null pointers or strides too short.
bool narrowSamplesTo8Bits(const std::uint8_t* src, int width, int height, int src_stride_bytes, int sample_bits,
                          std::uint8_t* dst, int dst_stride_bytes, std::string* error);

}  // namespace telesphere::robot::cameras
