// SPDX-License-Identifier: MIT
/// @brief Why a calibration file could not be read or written: the file, the 1-based line (0 when
///        unknown), the field (dotted path such as "cameras[1].intrinsics.alpha") and what is
///        wrong. FileResult<T> carries either the value or the error (STYLE.md §13: an expected
///        failure is a value, not an exception, at the API).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace telesphere::calib {

struct FileError {
  std::string path;
  int line = 0;
  std::string field;
  std::string message;

  /// "path:line: field: message" (line and field left out when unknown).
  std::string describe() const {
    // Appends only: GCC 12 at -O3 warns falsely (-Wrestrict, bug 105329) on string operator+.
    std::string out = path;
    if (line > 0) out.append(":").append(std::to_string(line));
    out.append(": ");
    if (!field.empty()) out.append(field).append(": ");
    out.append(message);
    return out;
  }
};

/// Thrown inside the readers and caught at the API boundary into a FileResult.
struct FileErrorException : std::runtime_error {
  explicit FileErrorException(FileError e) : std::runtime_error(e.describe()), error(std::move(e)) {}
  FileError error;
};

template <typename T>
class FileResult {
 public:
  FileResult(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design
  FileResult(FileError error) : error_(std::move(error)) {}  // NOLINT
  explicit operator bool() const { return value_.has_value(); }
  const T& operator*() const { return *value_; }
  T& operator*() { return *value_; }
  const T* operator->() const { return &*value_; }
  const FileError& error() const { return error_; }

 private:
  std::optional<T> value_;
  FileError error_;
};

}  // namespace telesphere::calib
