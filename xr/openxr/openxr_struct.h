// SPDX-License-Identifier: MIT
/// @brief A zero-initialised OpenXR input/output structure with its `type` set: OpenXR
///        structures must carry their XrStructureType and a null `next` (unless chained).
#pragma once

#include <openxr/openxr.h>

namespace telesphere::xr::openxr {

template <typename T>
T xrStruct(XrStructureType type) {
  T value{};
  value.type = type;
  return value;
}

}  // namespace telesphere::xr::openxr
