// SPDX-License-Identifier: MIT
/// @brief What every `telesphere-calib` command shares: loading a calibration file (any of our
///        three formats) with the reason on stderr, and progress lines on stderr.
#pragma once

#include <iostream>
#include <optional>
#include <string>

#include "calib/calibration_file.h"

namespace telesphere::app {

/// The calibration in `path`, or nothing after saying why on stderr.
inline std::optional<calib::SystemCalibration> loadCalibrationOrSay(const std::string& path) {
  auto result = calib::loadCalibrationFile(path);
  if (!result) {
    std::cerr << "telesphere-calib: " << result.error().describe() << "\n";
    return std::nullopt;
  }
  return *result;
}

inline void progressLine(const std::string& line) { std::cerr << line << "\n"; }

}  // namespace telesphere::app
