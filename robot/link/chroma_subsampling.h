// SPDX-License-Identifier: MIT
/// @brief JPEG chroma subsampling, one enum for the whole video path (DESIGN.md §4): the robot's
///        encoder is set with it, the link names it (proto ChromaSubsampling, converted in
///        robot/link/proto_enums.h only), the XR app's decoder reports it for each image.
#pragma once

namespace telesphere::link {

enum class ChromaSubsampling { k420, k422, k444, kGray };

}  // namespace telesphere::link
