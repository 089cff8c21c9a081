// SPDX-License-Identifier: MIT
/// @brief libFuzzer target: arbitrary bytes as a link message. The first byte splits the input
///        into an envelope and two image parts (as a three-part ZeroMQ frame message would arrive);
///        parsing and frame checks must never crash, leak or read out of bounds.
#include <cstddef>
#include <cstdint>

#include "robot/link/link_schema.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t rest = size - 1;
  const std::size_t envelope_size = rest * data[0] / 255;
  const std::size_t left = (rest - envelope_size) / 2;
  const std::size_t right = rest - envelope_size - left;
  using namespace telesphere::link;
  DropReason why{};
  const auto envelope = parseEnvelope(data + 1, envelope_size, &why);
  if (envelope && envelope->has_stereo_frame()) {
    const auto bad = checkStereoFrame(envelope->stereo_frame(), left, right);
    if (!bad) {
      // A frame that passed must describe images we can afford to decode.
      const auto& l = envelope->stereo_frame().left();
      if (l.width() > kMaxImageSide || l.height() > kMaxImageSide) __builtin_trap();
    }
  }
  return 0;
}
