// SPDX-License-Identifier: MIT
/// @brief Format detection, file reading and atomic writing of calibration files.
#include "calib/calibration_file.h"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "calib/basalt_calibration.h"
#include "calib/kalibr_camchain.h"
#include "calib/system_calibration_yaml.h"

namespace telesphere::calib {

std::string_view formatName(CalibrationFormat format) {
  switch (format) {
    case CalibrationFormat::kTelesphere: return "telesphere";
    case CalibrationFormat::kKalibr: return "kalibr";
    case CalibrationFormat::kBasalt: return "basalt";
  }
  return "?";
}

std::optional<CalibrationFormat> parseFormatName(std::string_view name) {
  for (auto f : {CalibrationFormat::kTelesphere, CalibrationFormat::kKalibr, CalibrationFormat::kBasalt})
    if (formatName(f) == name) return f;
  return std::nullopt;
}

std::optional<CalibrationFormat> detectCalibrationFormat(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return std::nullopt;
  if (text[first] == '{') {
    return text.find("\"value0\"") != std::string::npos ? std::optional(CalibrationFormat::kBasalt)
                                                        : std::nullopt;
  }
  try {
    const YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) return std::nullopt;
    if (root["version"].IsDefined() && root["cameras"].IsDefined()) return CalibrationFormat::kTelesphere;
    if (root["cam0"].IsDefined()) return CalibrationFormat::kKalibr;
  } catch (const YAML::Exception&) {
    // A YAML syntax error: let our own reader report it with its line.
    if (text.find("cam0:") == std::string::npos) return CalibrationFormat::kTelesphere;
    return CalibrationFormat::kKalibr;
  }
  return std::nullopt;
}

FileResult<SystemCalibration> parseCalibration(const std::string& text, const std::string& path) {
  const auto format = detectCalibrationFormat(text);
  if (!format)
    return FileError{path, 0, "",
                     "not a calibration file we know (ours: YAML with version and cameras; kalibr: "
                     "camchain YAML with cam0; Basalt: JSON with value0)"};
  switch (*format) {
    case CalibrationFormat::kTelesphere: return parseSystemCalibrationYaml(text, path);
    case CalibrationFormat::kKalibr: return parseKalibrCamchain(text, path);
    case CalibrationFormat::kBasalt: return parseBasaltCalibration(text, path);
  }
  return FileError{path, 0, "", "unknown format"};
}

FileResult<SystemCalibration> loadCalibrationFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return FileError{path, 0, "", std::string("cannot open: ") + std::strerror(errno)};
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) return FileError{path, 0, "", "read error"};
  return parseCalibration(text.str(), path);
}

std::optional<FileError> saveCalibrationFile(const SystemCalibration& calibration,
                                             const std::string& path, CalibrationFormat format) {
  if (auto problem = calibration.inconsistency())
    return FileError{path, 0, problem->first, "refusing to write: " + problem->second};
  std::string text;
  switch (format) {
    case CalibrationFormat::kTelesphere: text = toSystemCalibrationYaml(calibration); break;
    case CalibrationFormat::kKalibr: text = toKalibrCamchain(calibration); break;
    case CalibrationFormat::kBasalt: text = toBasaltCalibration(calibration); break;
  }
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return FileError{path, 0, "", std::string("cannot write: ") + std::strerror(errno)};
    out << text;
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      return FileError{path, 0, "", "write failed (disk full?)"};
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    return FileError{path, 0, "", "cannot rename into place: " + why};
  }
  return std::nullopt;
}

}  // namespace telesphere::calib
