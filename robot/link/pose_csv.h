// SPDX-License-Identifier: MIT
/// @brief A pose as seven CSV columns — `<prefix>_tx, _ty, _tz` (m) and `_qx, _qy, _qz, _qw` (unit
///        quaternion), the link's Pose convention — for the files that record poses beside the link
///        (the simulation's ground truth, the operator app's projection maps; app/bench/truth reads them).
#pragma once

#include <Eigen/Geometry>
#include <ostream>
#include <string>

namespace telesphere::link {

/// The seven column names, each preceded by a comma: ",<prefix>_tx,…,<prefix>_qw".
inline std::string poseCsvHeader(const std::string& prefix) {
  std::string out;
  for (const char* c : {"tx", "ty", "tz", "qx", "qy", "qz", "qw"}) out += "," + prefix + "_" + c;
  return out;
}

/// The seven values of T, each preceded by a comma (the stream's precision applies).
inline void writePoseCsv(std::ostream& out, const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Eigen::Vector3d& t = T.translation();
  out << ',' << t.x() << ',' << t.y() << ',' << t.z() << ',' << q.x() << ',' << q.y() << ',' << q.z() << ','
      << q.w();
}

}  // namespace telesphere::link
