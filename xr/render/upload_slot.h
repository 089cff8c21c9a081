// SPDX-License-Identifier: MIT
/// @brief Where one decoded image's planes sit when the decoder wrote them straight into GL
///        buffer memory (a slot of the UploadRing, DESIGN.md §4): the same bytes twice, as offsets
///        into the buffer (the GL copies them into the plane textures from there) and as pointers
///        into its persistent mapping (the decoder writes, CPU readers read). GL-free on purpose:
///        YuvPlanes carries it, and the decoder threads never touch GL.
#pragma once

#include <cstddef>
#include <cstdint>

namespace telesphere::xr::render {

/// The sizes of one image's planes: what a slot is made for.
struct PlaneLayout {
  int width = 0, height = 0;
  int chroma_width = 0, chroma_height = 0;  ///< 0 × 0: greyscale (Y only)

  std::size_t lumaBytes() const { return std::size_t(width) * std::size_t(height); }
  std::size_t chromaBytes() const { return std::size_t(chroma_width) * std::size_t(chroma_height); }
  std::size_t bytes() const { return lumaBytes() + 2 * chromaBytes(); }
  bool operator==(const PlaneLayout&) const = default;
};

struct UploadSlot {
  unsigned int buffer = 0;  ///< GL buffer name (read as GL_PIXEL_UNPACK_BUFFER)
  std::size_t y_offset = 0, u_offset = 0, v_offset = 0;  ///< bytes into `buffer`
  std::uint8_t* y = nullptr;  ///< the same bytes, mapped (u, v null for greyscale)
  std::uint8_t* u = nullptr;
  std::uint8_t* v = nullptr;
  PlaneLayout layout;
  int index = 0;  ///< in its ring buffer
};

}  // namespace telesphere::xr::render
