// SPDX-License-Identifier: MIT
/// @brief A decoded image's YUV planes exactly as the JPEG decoder wrote them (Y full size, Cb
///        and Cr subsampled): what the decode pool hands to the renderer through a shared pointer,
///        so the planes are never copied between decode and upload (DESIGN.md §4). The bytes are
///        the planes' own vectors, or a slot of GL buffer memory the decoder wrote into (then the
///        GL copies them to the textures without the render thread touching a byte); read them
///        through yPlane(), uPlane(), vPlane() either way.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "robot/link/chroma_subsampling.h"
#include "xr/render/upload_slot.h"

namespace telesphere::xr::render {

/// Planes with rows tightly packed (stride = width). For kGray, u and v are empty.
struct YuvPlanes {
  int width = 0;
  int height = 0;
  int chroma_width = 0;
  int chroma_height = 0;
  /// As the JPEG was encoded; nothing: planes not from a JPEG (any chroma size, SourceImage::yuv).
  std::optional<link::ChromaSubsampling> subsampling = link::ChromaSubsampling::k420;
  std::vector<std::uint8_t> y, u, v;  ///< own memory; empty when `slot` holds the planes
  /// Set when the decoder wrote the planes into GL buffer memory (UploadRing) instead of y, u, v:
  /// the slot goes back to its ring once the last holder of these planes lets go (and the GL has
  /// finished copying from it).
  std::shared_ptr<const UploadSlot> slot;

  PlaneLayout layout() const { return {width, height, chroma_width, chroma_height}; }
  std::span<const std::uint8_t> yPlane() const {
    return slot ? std::span<const std::uint8_t>(slot->y, layout().lumaBytes()) : std::span<const std::uint8_t>(y);
  }
  std::span<const std::uint8_t> uPlane() const { return chromaPlane(slot ? slot->u : nullptr, u); }
  std::span<const std::uint8_t> vPlane() const { return chromaPlane(slot ? slot->v : nullptr, v); }
  std::span<const std::uint8_t> chromaPlane(const std::uint8_t* in_slot, const std::vector<std::uint8_t>& own) const {
    if (!slot) return own;
    return in_slot ? std::span<const std::uint8_t>(in_slot, layout().chromaBytes()) : std::span<const std::uint8_t>();
  }
};

}  // namespace telesphere::xr::render
