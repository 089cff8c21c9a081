// SPDX-License-Identifier: MIT
/// @brief YamlReader: typed access with file:line:field errors.
#include "calib/yaml_reader.h"

#include <cmath>
#include <sstream>

namespace telesphere::calib::detail {

YAML::Node YamlReader::parse(const std::string& text) const {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw FileErrorException(FileError{path_, e.mark.line + 1, "", "YAML syntax: " + e.msg});
  }
}

void YamlReader::fail(const YAML::Node& node, const std::string& field,
                      const std::string& message) const {
  const int line = node.IsDefined() && node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
  throw FileErrorException(FileError{path_, line, field, message});
}

void YamlReader::failAtKey(const YAML::Node& map, const std::string& key, const std::string& field,
                           const std::string& message) const {
  if (map.IsMap())
    for (const auto& kv : map)
      if (kv.first.Scalar() == key)
        throw FileErrorException(FileError{path_, kv.first.Mark().line + 1, field, message});
  fail(map, field, message);
}

int YamlReader::lineOf(const YAML::Node& root, const std::string& field) const {
  YAML::Node node = root;
  int line = root.Mark().line + 1;
  std::string rest = field;
  while (!rest.empty()) {
    const auto dot = rest.find('.');
    const std::string part = rest.substr(0, dot);
    rest = dot == std::string::npos ? "" : rest.substr(dot + 1);
    const auto bracket = part.find('[');
    const std::string key = part.substr(0, bracket);
    bool found = false;
    if (node.IsMap()) {
      for (const auto& kv : node) {
        if (kv.first.Scalar() != key) continue;
        line = kv.first.Mark().line + 1;
        node = kv.second;
        found = true;
        break;
      }
    }
    if (!found) break;
    if (bracket != std::string::npos) {
      const auto index = static_cast<std::size_t>(std::stoul(part.substr(bracket + 1)));
      if (!node.IsSequence() || index >= node.size()) break;
      node = node[index];
      line = node.Mark().line + 1;
    }
  }
  return line;
}

YAML::Node YamlReader::require(const YAML::Node& parent, const char* key,
                               const std::string& field) const {
  if (!parent.IsMap()) fail(parent, field, "expected a map");
  const YAML::Node node = parent[key];
  if (!node.IsDefined() || node.IsNull()) fail(parent, field, "missing");
  return node;
}

double YamlReader::number(const YAML::Node& node, const std::string& field) const {
  if (!node.IsScalar()) fail(node, field, "expected a number");
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) fail(node, field, "\"" + node.Scalar() + "\" is not a finite number");
    return v;
  } catch (const YAML::BadConversion&) {
    fail(node, field, "\"" + node.Scalar() + "\" is not a number");
  }
}

int YamlReader::integer(const YAML::Node& node, const std::string& field) const {
  if (!node.IsScalar()) fail(node, field, "expected an integer");
  try {
    return node.as<int>();
  } catch (const YAML::BadConversion&) {
    fail(node, field, "\"" + node.Scalar() + "\" is not an integer");
  }
}

std::string YamlReader::text(const YAML::Node& node, const std::string& field) const {
  if (!node.IsScalar()) fail(node, field, "expected a string");
  return node.Scalar();
}

std::vector<double> YamlReader::numbers(const YAML::Node& node, const std::string& field,
                                        int expected_size) const {
  if (!node.IsSequence()) fail(node, field, "expected a list of numbers");
  if (expected_size >= 0 && static_cast<int>(node.size()) != expected_size)
    fail(node, field,
         "expected " + std::to_string(expected_size) + " numbers, got " + std::to_string(node.size()));
  std::vector<double> out;
  for (std::size_t i = 0; i < node.size(); ++i)
    out.push_back(number(node[i], field + "[" + std::to_string(i) + "]"));
  return out;
}

Eigen::Isometry3d YamlReader::transform(const YAML::Node& node, const std::string& field) const {
  if (!node.IsMap()) fail(node, field, "expected {translation: [x, y, z], rotation_xyzw: [qx, qy, qz, qw]}");
  onlyKeys(node, field, {"translation", "rotation_xyzw"});
  const auto t = numbers(require(node, "translation", field + ".translation"), field + ".translation", 3);
  const YAML::Node q_node = require(node, "rotation_xyzw", field + ".rotation_xyzw");
  const auto q = numbers(q_node, field + ".rotation_xyzw", 4);
  const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0) > 1e-6) {
    std::ostringstream os;
    os.precision(17);
    os << "has norm " << quat.norm() << ", not a unit quaternion";
    fail(q_node, field + ".rotation_xyzw", os.str());
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = quat.normalized().toRotationMatrix();
  T.translation() << t[0], t[1], t[2];
  return T;
}

Eigen::Isometry3d YamlReader::matrix4(const YAML::Node& node, const std::string& field) const {
  if (!node.IsSequence() || node.size() != 4) fail(node, field, "expected a 4x4 matrix (4 rows)");
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r) {
    const auto row = numbers(node[r], field + "[" + std::to_string(r) + "]", 4);
    for (int c = 0; c < 4; ++c) M(r, c) = row[c];
  }
  if ((M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9)
    fail(node[3], field + "[3]", "last row must be [0, 0, 0, 1]");
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  const double err = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (err > 1e-6 || R.determinant() < 0) {
    std::ostringstream os;
    os << "rotation part is not orthonormal with determinant +1 (|RᵀR − I| = " << err << ")";
    fail(node, field, os.str());
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T.translation() = M.topRightCorner<3, 1>();
  return T;
}

void YamlReader::onlyKeys(const YAML::Node& map, const std::string& field,
                          std::initializer_list<const char*> allowed) const {
  for (const auto& kv : map) {
    const std::string key = kv.first.as<std::string>();
    bool known = false;
    for (const char* a : allowed) known = known || key == a;
    if (!known) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(kv.first, field.empty() ? key : field + "." + key,
           "unknown field (expected one of: " + list + ")");
    }
  }
}

}  // namespace telesphere::calib::detail
