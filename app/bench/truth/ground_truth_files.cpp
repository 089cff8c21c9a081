// SPDX-License-Identifier: MIT
/// @brief Readers of the ground-truth files (see ground_truth_files.h).
#include "app/bench/truth/ground_truth_files.h"

#include <fstream>
#include <sstream>

namespace telesphere::truth {
namespace {

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

/// Header name → column.
std::map<std::string, std::size_t> columnsOf(const std::string& header) {
  std::map<std::string, std::size_t> columns;
  const auto names = splitCsv(header);
  for (std::size_t i = 0; i < names.size(); ++i) columns[names[i]] = i;
  return columns;
}

struct Row {
  const std::vector<std::string>& cells;
  const std::map<std::string, std::size_t>& columns;
  std::string* missing;

  const std::string& text(const std::string& name) const {
    static const std::string empty;
    const auto it = columns.find(name);
    if (it == columns.end() || it->second >= cells.size()) {
      if (missing->empty()) *missing = "no column " + name;
      return empty;
    }
    return cells[it->second];
  }
  double number(const std::string& name) const {
    const std::string& t = text(name);
    try {
      return std::stod(t);
    } catch (...) {
      if (missing->empty()) *missing = "column " + name + " is not a number: '" + t + "'";
      return 0.0;
    }
  }
  std::int64_t integer(const std::string& name) const {
    const std::string& t = text(name);
    try {
      return std::stoll(t);
    } catch (...) {
      if (missing->empty()) *missing = "column " + name + " is not an integer: '" + t + "'";
      return 0;
    }
  }
  Eigen::Isometry3d pose(const std::string& prefix) const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << number(prefix + "_tx"), number(prefix + "_ty"), number(prefix + "_tz");
    Eigen::Quaterniond q(number(prefix + "_qw"), number(prefix + "_qx"), number(prefix + "_qy"), number(prefix + "_qz"));
    T.linear() = q.normalized().toRotationMatrix();
    return T;
  }
};

}  // namespace

std::optional<std::map<std::uint64_t, RobotTruthRow>> loadRobotTruth(const std::string& path, std::string* error) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line)) {
    *error = path + ": cannot read the robot's ground truth";
    return std::nullopt;
  }
  const auto columns = columnsOf(line);
  std::map<std::uint64_t, RobotTruthRow> rows;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const auto cells = splitCsv(line);
    std::string why;
    const Row row{cells, columns, &why};
    RobotTruthRow r;
    r.sequence = static_cast<std::uint64_t>(row.integer("sequence"));
    r.capture_ns = {row.integer("capture_ns_left"), row.integer("capture_ns_right")};
    for (int side = 0; side < 2; ++side) {
      const std::string prefix = side == 0 ? "true_left" : "true_right";
      if (!row.text(prefix + "_tx").empty()) r.T_robot_cam_true[side] = row.pose(prefix);
    }
    r.mapping_set = row.integer("mapping_set") != 0;
    r.T_robot_vr = row.pose("robot_vr");
    if (!why.empty()) {
      *error = path + ":" + std::to_string(number) + ": " + why;
      return std::nullopt;
    }
    rows[r.sequence] = r;
  }
  return rows;
}

std::optional<std::vector<XrTruthFrame>> loadXrTruthFrames(const std::string& dir, std::string* error) {
  const std::string path = dir + "/frames.csv";
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line)) {
    *error = path + ": cannot read the operator app's projection-map index";
    return std::nullopt;
  }
  const auto columns = columnsOf(line);
  std::vector<XrTruthFrame> frames;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const auto cells = splitCsv(line);
    std::string why;
    const Row row{cells, columns, &why};
    XrTruthFrame f;
    f.index = static_cast<std::uint64_t>(row.integer("index"));
    f.display_ns = row.integer("display_ns");
    f.stereo_sequence = static_cast<std::uint64_t>(row.integer("stereo_sequence"));
    f.capture_ns = row.integer("capture_ns");
    f.mode = row.text("mode");
    f.radius_m = row.number("radius_m");
    f.ipd_m = row.number("ipd_m");
    f.fov = {row.number("fov_left"), row.number("fov_right"), row.number("fov_up"), row.number("fov_down")};
    f.width = static_cast<int>(row.integer("width"));
    f.height = static_cast<int>(row.integer("height"));
    f.image_width = static_cast<int>(row.integer("image_width"));
    f.image_height = static_cast<int>(row.integer("image_height"));
    f.T_vr_hmd = row.pose("hmd");
    f.T_robot_vr_used = row.pose("robot_vr");
    f.T_robot_cam_stamped = {row.pose("cam_left"), row.pose("cam_right")};
    if (why.empty() && (f.width <= 0 || f.height <= 0 || f.width > 8192 || f.height > 8192))
      why = "eye size " + std::to_string(f.width) + "x" + std::to_string(f.height) + " is not valid";
    if (!why.empty()) {
      *error = path + ":" + std::to_string(number) + ": " + why;
      return std::nullopt;
    }
    frames.push_back(f);
  }
  return frames;
}

std::optional<std::vector<float>> loadProjectionMap(const std::string& dir, const XrTruthFrame& frame,
                                                    std::string* error) {
  const std::string path = dir + "/map_" + std::to_string(frame.index) + ".f32";
  std::ifstream in(path, std::ios::binary);
  std::vector<float> map(static_cast<std::size_t>(frame.width) * frame.height * 4);
  in.read(reinterpret_cast<char*>(map.data()), static_cast<std::streamsize>(map.size() * sizeof(float)));
  if (!in || in.peek() != std::char_traits<char>::eof()) {
    *error = path + ": not a " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
             " projection map pair";
    return std::nullopt;
  }
  return map;
}

}  // namespace telesphere::truth
