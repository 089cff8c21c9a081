// SPDX-License-Identifier: MIT
/// @brief Scalar helpers shared by the camera models so that one template serves double, float
///        and ceres::Jet: finiteness and value extraction without including Ceres here.
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>

namespace ceres {
template <typename T, int N>
struct Jet;
}  // namespace ceres

namespace telesphere::calib {

/// The real part of a scalar as a double (the value of a Jet, the number itself otherwise).
inline double scalarValue(double s) { return s; }
inline double scalarValue(float s) { return static_cast<double>(s); }
template <typename T, int N>
double scalarValue(const ceres::Jet<T, N>& s) {
  return scalarValue(s.a);
}

/// True when the scalar's value is finite (for a Jet: its value; derivatives follow it).
inline bool isFiniteScalar(double s) { return std::isfinite(s); }
inline bool isFiniteScalar(float s) { return std::isfinite(s); }
template <typename T, int N>
bool isFiniteScalar(const ceres::Jet<T, N>& s) {
  return isFiniteScalar(s.a);
}

/// Relative precision we can expect from Scalar's arithmetic (a Jet inherits its value type's).
template <typename Scalar>
constexpr double scalarEpsilon() {
  if constexpr (std::is_same_v<Scalar, float>) {
    return 1.1920928955078125e-07;
  } else if constexpr (std::is_same_v<Scalar, double>) {
    return 2.220446049250313e-16;
  } else {
    return scalarEpsilon<decltype(Scalar::a)>();
  }
}

}  // namespace telesphere::calib

namespace telesphere::calib {

/// Underlying floating-point type of a scalar (float, double, or a Jet's value type).
template <typename Scalar>
struct ValueType {
  using type = Scalar;
};
template <typename T, int N>
struct ValueType<ceres::Jet<T, N>> {
  using type = typename ValueType<T>::type;
};

/// True when a squared norm is far enough from underflow and overflow that the camera models'
/// products of squares and quotients stay normal numbers. Outside (or NaN) the models rescale the
/// point first: projection is invariant to the point's scale.
template <typename Scalar>
bool squaredNormInSafeRange(const Scalar& squared_norm) {
  using V = typename ValueType<Scalar>::type;
  constexpr double lo = static_cast<double>(std::numeric_limits<V>::min()) / scalarEpsilon<V>();
  constexpr double hi = static_cast<double>(std::numeric_limits<V>::max()) * scalarEpsilon<V>();
  const double v = scalarValue(squared_norm);
  return v >= lo && v <= hi;
}

}  // namespace telesphere::calib
