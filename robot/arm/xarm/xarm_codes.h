// SPDX-License-Identifier: MIT
/// @brief The xArm controller's error and warning codes as text (UFACTORY's published tables,
///        shown by their Studio as "C<n>"; robot/arm/xarm/README.md gives the source), so that the
///        supervisor reads "C22 self-collision" instead of a number.
#pragma once

#include <string>

namespace telesphere::xarm {

/// "C22 self-collision error"; code 0: "no error"; unknown codes: "C<n> (unknown error code)".
std::string controllerErrorText(int code);
/// "warning 11: the controller's command cache is full"; code 0: "no warning".
std::string controllerWarningText(int code);
/// True for the emergency stops (1, 2, 3): they clear only once the button or input is released.
bool isEmergencyStop(int code);

}  // namespace telesphere::xarm
