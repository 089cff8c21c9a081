// SPDX-License-Identifier: MIT
/// @brief Hiding what the link lost (DESIGN.md §9): the media path fills a lost JPEG band with
///        mid grey and says which image rows it covers; the operator side paints those rows from
///        the previous decoded image of the same size, so the operator sees a band a frame old,
///        not a grey stripe. Without such an image the rows stay grey (counted).
#pragma once

#include <utility>
#include <vector>

#include "xr/render/yuv_planes.h"

namespace telesphere::xr::video {

/// Paints `lost` rows (luma rows [first, end), clamped to the image) of `target` from `previous`
/// (null, or another layout: left grey); chroma rows follow in proportion. `target` must not be
/// shared yet: its planes (own memory or its upload slot) are written. Returns (rows painted,
/// rows left grey).
std::pair<int, int> concealRows(const render::YuvPlanes& target, const render::YuvPlanes* previous,
                                const std::vector<std::pair<int, int>>& lost);

}  // namespace telesphere::xr::video
