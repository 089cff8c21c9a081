// SPDX-License-Identifier: MIT
/// @brief Reading YAML with errors that name the file, the line and the field (internal to calib:
///        shared by our calibration format and the kalibr importer).
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <initializer_list>
#include <string>
#include <vector>

#include "calib/file_error.h"
#include "calib/system_calibration.h"

namespace telesphere::calib::detail {

class YamlReader {
 public:
  explicit YamlReader(std::string path) : path_(std::move(path)) {}

  /// Parses text; a syntax error becomes a FileErrorException with its line.
  YAML::Node parse(const std::string& text) const;

  [[noreturn]] void fail(const YAML::Node& node, const std::string& field,
                         const std::string& message) const;
  /// Fails at the line of `key` in `map` (the key's own line, also when its value is empty).
  [[noreturn]] void failAtKey(const YAML::Node& map, const std::string& key,
                              const std::string& field, const std::string& message) const;
  /// The 1-based line of the dotted `field` ("cameras[1].intrinsics") in root, as far as it
  /// exists (the deepest existing key's line).
  int lineOf(const YAML::Node& root, const std::string& field) const;

  /// parent[key], which must exist (else an error at the parent's line naming field).
  YAML::Node require(const YAML::Node& parent, const char* key, const std::string& field) const;
  double number(const YAML::Node& node, const std::string& field) const;
  int integer(const YAML::Node& node, const std::string& field) const;
  std::string text(const YAML::Node& node, const std::string& field) const;
  /// A sequence of numbers; expected_size < 0 accepts any length.
  std::vector<double> numbers(const YAML::Node& node, const std::string& field,
                              int expected_size = -1) const;
  /// {translation: [x, y, z], rotation_xyzw: [qx, qy, qz, qw]}, the quaternion unit to 1e-6.
  Eigen::Isometry3d transform(const YAML::Node& node, const std::string& field) const;
  /// A 4×4 homogeneous matrix as four rows; the rotation orthonormal to 1e-6 (re-orthonormalised).
  Eigen::Isometry3d matrix4(const YAML::Node& node, const std::string& field) const;
  /// Fails on a key of a map outside `allowed` (catches typos such as "alhpa").
  void onlyKeys(const YAML::Node& map, const std::string& field,
                std::initializer_list<const char*> allowed) const;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// Parses `text` and runs read(reader, root), turning every failure into a FileError.
template <typename Read>
FileResult<SystemCalibration> readYamlCalibration(const std::string& text, const std::string& path,
                                                  Read&& read) {
  try {
    const YamlReader in(path);
    return read(in, in.parse(text));
  } catch (const FileErrorException& e) {
    return e.error;
  } catch (const YAML::Exception& e) {
    return FileError{path, e.mark.line + 1, "", e.msg};
  }
}

}  // namespace telesphere::calib::detail
