// SPDX-License-Identifier: MIT
/// @brief Which camera of the stereo pair: the one camera-side type of the robot (pairing, the
///        joint-state buffer's camera poses, stills, truth), its values usable as an index (0, 1).
#pragma once

namespace telesphere::robot::cameras {

enum class CameraSide { kLeft = 0, kRight = 1 };

}  // namespace telesphere::robot::cameras
