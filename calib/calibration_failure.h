// SPDX-License-Identifier: MIT
/// @brief Why a calibration could not produce a trustworthy result (STYLE.md §13: an expected
///        failure is a value): too few views, a target never seen, unidentifiable unknowns, a
///        diverging solve. SolveResult<T> carries either the result or the failure.
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace telesphere::calib {

enum class CalibrationError {
  kTargetNeverSeen,   ///< no view holds enough corners of the target
  kTooFewViews,       ///< fewer usable views (or samples) than the solve needs
  kNoCommonViews,     ///< stereo: no view sees the target in both cameras
  kNotIdentifiable,   ///< the data cannot separate the unknowns (hand-eye motion too poor)
  kInitialisationFailed,
  kDiverged,          ///< the solve failed or ended with an implausible error
};

struct CalibrationFailure {
  CalibrationError code;
  std::string message;  ///< what is wrong and what to do about it, for the user
};

template <typename T>
class SolveResult {
 public:
  SolveResult(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design
  SolveResult(CalibrationFailure failure) : failure_(std::move(failure)) {}  // NOLINT
  explicit operator bool() const { return value_.has_value(); }
  const T& operator*() const { return *value_; }
  T& operator*() { return *value_; }
  const T* operator->() const { return &*value_; }
  T* operator->() { return &*value_; }
  const CalibrationFailure& failure() const { return *failure_; }

 private:
  std::optional<T> value_;
  std::optional<CalibrationFailure> failure_;
};

}  // namespace telesphere::calib
