// SPDX-License-Identifier: MIT
/// @brief chooseSwapchainFormat: sRGB first, linear as the fallback.
#include "xr/openxr/openxr_swapchain_format.h"

#include <algorithm>
#include <array>
#include <sstream>

namespace telesphere::xr::openxr {
namespace {

// GL internal formats (glcorearb.h values; spelled out to keep this file free of GL headers).
constexpr std::int64_t kGlSrgb8Alpha8 = 0x8C43;
constexpr std::int64_t kGlSrgb8 = 0x8C41;
constexpr std::int64_t kGlRgba8 = 0x8058;
constexpr std::int64_t kGlRgb10A2 = 0x8059;
constexpr std::int64_t kGlRgba16f = 0x881A;

constexpr std::array<std::int64_t, 2> kSwapchainSrgbFormats{kGlSrgb8Alpha8, kGlSrgb8};
constexpr std::array<std::int64_t, 3> kSwapchainLinearFormats{kGlRgba8, kGlRgb10A2, kGlRgba16f};

template <std::size_t N>
std::optional<std::int64_t> firstOffered(const std::vector<std::int64_t>& offered,
                                         const std::array<std::int64_t, N>& usable) {
  for (const std::int64_t f : offered)
    if (std::find(usable.begin(), usable.end(), f) != usable.end()) return f;
  return std::nullopt;
}

}  // namespace

std::string glFormatName(std::int64_t format) {
  switch (format) {
    case kGlSrgb8Alpha8: return "GL_SRGB8_ALPHA8";
    case kGlSrgb8: return "GL_SRGB8";
    case kGlRgba8: return "GL_RGBA8";
    case kGlRgb10A2: return "GL_RGB10_A2";
    case kGlRgba16f: return "GL_RGBA16F";
    default: break;
  }
  std::ostringstream os;
  os << "0x" << std::hex << format;
  return os.str();
}

std::optional<SwapchainFormatChoice> chooseSwapchainFormat(const std::vector<std::int64_t>& offered,
                                                           SwapchainColour wanted) {
  const auto srgb = firstOffered(offered, kSwapchainSrgbFormats);
  const auto linear = firstOffered(offered, kSwapchainLinearFormats);
  if (wanted == SwapchainColour::kLinear) {
    if (linear) return SwapchainFormatChoice{*linear, false};
    if (srgb) return SwapchainFormatChoice{*srgb, true};
    return std::nullopt;
  }
  if (srgb) return SwapchainFormatChoice{*srgb, true};
  if (linear) return SwapchainFormatChoice{*linear, false};
  return std::nullopt;
}

}  // namespace telesphere::xr::openxr
