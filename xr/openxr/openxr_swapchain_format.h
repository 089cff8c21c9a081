// SPDX-License-Identifier: MIT
/// @brief Picks the OpenXR swapchain colour format from what the runtime offers (GL internal
///        formats, in the runtime's order of preference).
///
/// Colour: the spherical renderer writes sRGB-encoded values (camera images are sRGB and are
/// sampled without decoding). With an sRGB swapchain format (GL_SRGB8_ALPHA8) the bytes are
/// stored as written (GL_FRAMEBUFFER_SRGB off) and the compositor reads them as sRGB: correct.
/// With a linear format (GL_RGBA8, GL_RGB10_A2, GL_RGBA16F) the compositor would read the
/// encoded values as linear (too bright); the session then renders into an sRGB texture and
/// blits it to the swapchain with GL_FRAMEBUFFER_SRGB on, which decodes to linear.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace telesphere::xr::openxr {

enum class SwapchainColour { kAuto, kSrgb, kLinear };

struct SwapchainFormatChoice {
  std::int64_t format = 0;  ///< GL internal format
  bool srgb = false;        ///< true: stored bytes are sRGB-encoded
};

/// GL internal format name ("GL_SRGB8_ALPHA8", …) or its hex value.
std::string glFormatName(std::int64_t format);

/// The first format in `offered` that we can render to, sRGB formats first (kAuto, kSrgb) or
/// linear ones first (kLinear; for tests of the linear path). kSrgb and kLinear fall back to the
/// other kind when the runtime offers none of the wanted kind. Nothing when none is usable.
std::optional<SwapchainFormatChoice> chooseSwapchainFormat(const std::vector<std::int64_t>& offered,
                                                           SwapchainColour wanted);

}  // namespace telesphere::xr::openxr
