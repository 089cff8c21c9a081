// SPDX-License-Identifier: MIT
/// @brief kalibr Aprilgrid target: corner geometry and YAML description.
#include "calib/aprilgrid.h"

#include <fstream>
#include <sstream>

#include "calib/yaml_reader.h"

namespace telesphere::calib {

Eigen::Vector3d AprilGrid::cornerPosition(int corner_id) const {
  const int tag = corner_id / 4, k = corner_id % 4;
  const double x0 = (tag % tag_cols) * pitch();
  const double y0 = (tag / tag_cols) * pitch();
  const double dx = (k == 1 || k == 2) ? tag_size : 0.0;
  const double dy = (k == 2 || k == 3) ? tag_size : 0.0;
  return {x0 + dx, y0 + dy, 0.0};
}

std::vector<Eigen::Vector3d> AprilGrid::cornerPositions() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(static_cast<std::size_t>(numCorners()));
  for (int i = 0; i < numCorners(); ++i) out.push_back(cornerPosition(i));
  return out;
}

FileResult<AprilGrid> parseAprilGrid(const std::string& text, const std::string& path) {
  try {
    const detail::YamlReader reader(path);
    const YAML::Node root = reader.parse(text);
    if (!root.IsMap()) reader.fail(root, "", "not a kalibr target description (expected a map)");
    const std::string type = reader.text(reader.require(root, "target_type", "target_type"), "target_type");
    if (type != "aprilgrid")
      reader.failAtKey(root, "target_type", "target_type",
                       "target type '" + type + "' is not supported (only 'aprilgrid')");
    AprilGrid grid;
    grid.tag_cols = reader.integer(reader.require(root, "tagCols", "tagCols"), "tagCols");
    grid.tag_rows = reader.integer(reader.require(root, "tagRows", "tagRows"), "tagRows");
    grid.tag_size = reader.number(reader.require(root, "tagSize", "tagSize"), "tagSize");
    grid.tag_spacing = reader.number(reader.require(root, "tagSpacing", "tagSpacing"), "tagSpacing");
    if (grid.tag_cols < 1 || grid.tag_rows < 1 || grid.numTags() > 587)
      reader.failAtKey(root, "tagCols", "tagCols",
                       "the grid needs 1 to 587 tags (AprilTag 36h11 has 587), got " +
                           std::to_string(grid.tag_cols) + "x" + std::to_string(grid.tag_rows));
    if (!(grid.tag_size > 0.0 && grid.tag_size < 10.0))
      reader.failAtKey(root, "tagSize", "tagSize", "tagSize must be in (0, 10) m");
    if (!(grid.tag_spacing > 0.0 && grid.tag_spacing < 10.0))
      reader.failAtKey(root, "tagSpacing", "tagSpacing", "tagSpacing must be in (0, 10)");
    return grid;
  } catch (const FileErrorException& e) {
    return e.error;
  }
}

FileResult<AprilGrid> loadAprilGrid(const std::string& path) {
  std::ifstream in(path);
  if (!in) return FileError{path, 0, "", "cannot open the target file"};
  std::stringstream ss;
  ss << in.rdbuf();
  return parseAprilGrid(ss.str(), path);
}

}  // namespace telesphere::calib
