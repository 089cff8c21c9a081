// SPDX-License-Identifier: MIT
/// @brief Hand-eye sample file (see hand_eye_samples.h).
#include "calib/hand_eye_samples.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "calib/target_detection.h"
#include "calib/yaml_reader.h"

namespace telesphere::calib {

FileResult<HandEyeSampleFile> loadHandEyeSamples(const std::string& path,
                                                 const std::function<void(const std::string&)>& progress,
                                                 const HeadArmForwardKinematics& head_fk) {
  std::ifstream in(path);
  if (!in) return FileError{path, 0, "", "cannot open the sample file"};
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    const detail::YamlReader reader(path);
    const YAML::Node root = reader.parse(ss.str());
    HandEyeSampleFile file;
    const YAML::Node marker = reader.require(root, "marker", "marker");
    reader.onlyKeys(marker, "marker", {"dictionary", "id", "size"});
    file.dictionary = reader.text(reader.require(marker, "dictionary", "marker.dictionary"), "marker.dictionary");
    const auto names = arucoDictionaryNames();
    if (std::find(names.begin(), names.end(), file.dictionary) == names.end())
      reader.failAtKey(marker, "dictionary", "marker.dictionary", "unknown ArUco dictionary '" + file.dictionary + "'");
    file.marker_id = reader.integer(reader.require(marker, "id", "marker.id"), "marker.id");
    file.marker_size = reader.number(reader.require(marker, "size", "marker.size"), "marker.size");
    if (!(file.marker_size > 0)) reader.failAtKey(marker, "size", "marker.size", "the marker size must be positive");
    const YAML::Node samples = reader.require(root, "samples", "samples");
    if (!samples.IsSequence()) reader.fail(samples, "samples", "expected a list of samples");
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const std::string field = "samples[" + std::to_string(i) + "]";
      const YAML::Node s = samples[i];
      reader.onlyKeys(s, field, {"t_ns", "T_robot_flange", "q_head", "T_mount_wrist", "image_l", "image_r", "corners_l", "corners_r"});
      HandEyeSample sample;
      if (s["t_ns"]) sample.t_ns = static_cast<std::int64_t>(reader.number(s["t_ns"], field + ".t_ns"));
      if (s["T_robot_flange"] && s["q_head"])
        reader.failAtKey(s, "q_head", field + ".q_head", "give either T_robot_flange or q_head, not both");
      if (const YAML::Node q = s["q_head"]) {
        if (!q.IsSequence()) reader.fail(q, field + ".q_head", "expected a list of joint angles (rad)");
        const auto angles = reader.numbers(q, field + ".q_head", -1);
        if (!head_fk)
          reader.fail(q, field + ".q_head",
                      "joint angles need the head arm's forward kinematics, which this program lacks; "
                      "give T_robot_flange instead");
        std::string why;
        const auto T = head_fk(angles, &why);
        if (!T) reader.fail(q, field + ".q_head", why);
        sample.T_robot_flange = *T;
      } else {
        sample.T_robot_flange = reader.transform(reader.require(s, "T_robot_flange", field + ".T_robot_flange"),
                                                 field + ".T_robot_flange");
      }
      sample.T_mount_wrist = reader.transform(reader.require(s, "T_mount_wrist", field + ".T_mount_wrist"), field + ".T_mount_wrist");
      for (int c = 0; c < 2; ++c) {
        const std::string side = c == 0 ? "_l" : "_r";
        auto& corners = c == 0 ? sample.corners_l : sample.corners_r;
        if (const YAML::Node n = s["corners" + side]) {
          if (!n.IsSequence() || n.size() != 4) reader.fail(n, field + ".corners" + side, "expected four [u, v] corners");
          std::array<Eigen::Vector2d, 4> px;
          for (std::size_t k = 0; k < 4; ++k) {
            const auto uv = reader.numbers(n[k], field + ".corners" + side, 2);
            px[k] = Eigen::Vector2d(uv[0], uv[1]);
          }
          corners = px;
        } else if (const YAML::Node img = s["image" + side]) {
          const std::string file_name = (dir / reader.text(img, field + ".image" + side)).string();
          const auto image = readGrayImage(file_name);
          if (!image) reader.fail(img, field + ".image" + side, "cannot read the image " + file_name);
          corners = detectArucoMarker(*image, file.dictionary, file.marker_id);
          if (progress)
            progress("sample " + std::to_string(i + 1) + "/" + std::to_string(samples.size()) + " " +
                     file_name + (corners ? ": marker found" : ": marker not found"));
        }
      }
      file.samples.push_back(sample);
    }
    return file;
  } catch (const FileErrorException& e) {
    return e.error;
  }
}

}  // namespace telesphere::calib
