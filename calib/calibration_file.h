// SPDX-License-Identifier: MIT
/// @brief Reading and writing a calibration file in any of the formats we speak, the format
///        recognised from the content: JSON with "value0" → Basalt; YAML with "version" and
///        "cameras" → ours; YAML with "cam0" → kalibr camchain.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "calib/file_error.h"
#include "calib/system_calibration.h"

namespace telesphere::calib {

enum class CalibrationFormat { kTelesphere, kKalibr, kBasalt };

std::string_view formatName(CalibrationFormat format);
/// "telesphere", "kalibr" or "basalt".
std::optional<CalibrationFormat> parseFormatName(std::string_view name);

/// Which format `text` is in, or nothing when it is none of ours.
std::optional<CalibrationFormat> detectCalibrationFormat(const std::string& text);

/// Reads `path` (any format); unreadable files and bad content give an error naming the file,
/// the line where known and the field.
FileResult<SystemCalibration> loadCalibrationFile(const std::string& path);
FileResult<SystemCalibration> parseCalibration(const std::string& text, const std::string& path);

/// Writes `calibration` to `path` in `format`, through a temporary file renamed into place so that
/// a failed write never leaves half a file. Inconsistent calibrations are refused.
std::optional<FileError> saveCalibrationFile(const SystemCalibration& calibration,
                                             const std::string& path, CalibrationFormat format);

}  // namespace telesphere::calib
