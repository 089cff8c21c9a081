// SPDX-License-Identifier: MIT
/// @brief Short words in the operator's view without a font library: a 5 × 7 pixel font (digits,
///        capital letters and a few signs), each lit pixel a scissored clear, as the trial
///        indicator is drawn (no shader, no GL state left behind but the clear colour). For the
///        link's cues (link_state_overlay.h): a handful of characters per eye per frame.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "shaders/gl_api.h"

namespace telesphere::xr::frame_loop {

inline constexpr int kGlyphColumns = 5, kGlyphRows = 7;

/// The glyph of `c` as 7 rows of 5 bits (bit 4 the leftmost column), top row first; characters
/// the font lacks (and lower case is drawn as upper case) come back as a hollow box.
std::array<std::uint8_t, kGlyphRows> glyphOf(char c);

/// Width in pixels of `text` at `scale` pixels per font pixel (one column of space between glyphs).
int hudTextWidth(std::string_view text, int scale);

/// Draws `text` with its lower left corner at (x, y) (GL window coordinates) into the bound draw
/// framebuffer, `scale` pixels per font pixel, on a dark box one font pixel wider all round.
void drawHudText(std::string_view text, int x, int y, int scale, float r, float g, float b);

}  // namespace telesphere::xr::frame_loop
