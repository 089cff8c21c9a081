// SPDX-License-Identifier: MIT
#include "robot/arm/xarm/xarm_codes.h"

namespace telesphere::xarm {
namespace {

const char* errorMeaning(int code) {
  switch (code) {
    case 1: return "emergency stop button on the controller pushed in";
    case 2: return "emergency IO of the control box triggered";
    case 3: return "emergency stop button of the three-state switch pressed";
    case 10: return "servo motor error";
    case 11: return "servo motor 1 error";
    case 12: return "servo motor 2 error";
    case 13: return "servo motor 3 error";
    case 14: return "servo motor 4 error";
    case 15: return "servo motor 5 error";
    case 16: return "servo motor 6 error";
    case 17: return "servo motor 7 error";
    case 18: return "force/torque sensor communication error";
    case 19: return "end effector communication error";
    case 21: return "kinematic error";
    case 22: return "self-collision error";
    case 23: return "joint angle exceeds limit";
    case 24: return "speed exceeds limit";
    case 25: return "planning error";
    case 26: return "Linux real-time error";
    case 27: return "command reply error";
    case 28: return "end module communication error";
    case 30: return "feedback speed exceeds limit";
    case 31: return "collision caused abnormal current";
    case 32: return "three-point circle calculation error";
    case 33: return "controller GPIO error";
    case 34: return "recording timeout";
    case 35: return "safety boundary limit";
    case 36: return "too many delay commands";
    case 37: return "abnormal movement in manual mode";
    case 38: return "abnormal joint angle";
    case 39: return "abnormal communication between the power board's master and slave ICs";
    case 40: return "no error-free joint trajectory found";
    case 41: return "friction file content invalid";
    case 42: return "calibration file content invalid";
    case 50: return "six-axis force/torque sensor read error";
    case 51: return "six-axis force/torque sensor set-mode error";
    case 52: return "six-axis force/torque sensor set-zero error";
    case 53: return "six-axis force/torque sensor overloaded";
    case 60: return "linear speed exceeded the servo-mode limit";
    case 110: return "robot arm base board communication error";
    case 111: return "control box external RS-485 device communication error";
  }
  return nullptr;
}

const char* warningMeaning(int code) {
  switch (code) {
    case 11: return "the controller's command cache is full";
    case 12: return "command parameter error";
    case 13: return "no such command";
    case 14: return "the command has no solution";
    case 15: return "Modbus command buffer full";
  }
  return nullptr;
}

}  // namespace

std::string controllerErrorText(int code) {
  if (code == 0) return "no error";
  const char* meaning = errorMeaning(code);
  return "C" + std::to_string(code) + " " + (meaning ? meaning : "(unknown error code)");
}

std::string controllerWarningText(int code) {
  if (code == 0) return "no warning";
  const char* meaning = warningMeaning(code);
  return "warning " + std::to_string(code) + ": " + (meaning ? meaning : "(unknown warning code)");
}

bool isEmergencyStop(int code) { return code >= 1 && code <= 3; }

}  // namespace telesphere::xarm
