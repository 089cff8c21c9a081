// SPDX-License-Identifier: MIT
/// @brief views.csv: written a row at a time by the live run, read whole by the replay.
#include "xr/frame_loop/logged_view.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace telesphere::xr::frame_loop {
namespace {

constexpr const char* kHeader =
    "png,stereo_sequence,px,py,pz,qx,qy,qz,qw,image_saturation,link_age_ms,eye_camera_distance_m,stream_text,"
    "insecure_link";
constexpr const char* kHeaderWithoutInsecure =
    "png,stereo_sequence,px,py,pz,qx,qy,qz,qw,image_saturation,link_age_ms,eye_camera_distance_m,stream_text";
constexpr const char* kHeaderWithoutCues = "png,stereo_sequence,px,py,pz,qx,qy,qz,qw";

}  // namespace

bool appendLoggedView(const std::string& path, const LoggedView& view, std::string* error) {
  std::FILE* f = std::fopen(path.c_str(), "a");
  if (!f) {
    *error = path + ": " + std::strerror(errno);
    return false;
  }
  const bool fresh = std::fseek(f, 0, SEEK_END) == 0 && std::ftell(f) == 0;  // a new or empty file
  const Eigen::Vector3d p = view.T_vr_hmd.translation();
  const Eigen::Quaterniond q(view.T_vr_hmd.linear());
  if (fresh) std::fprintf(f, "%s\n", kHeader);
  std::fprintf(f, "%s,%llu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.9g,%.17g,%.17g,%s,%d\n", view.png.c_str(),
               static_cast<unsigned long long>(view.stereo_sequence), p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w(),
               static_cast<double>(view.image_saturation), view.link_state.image_age_ms,
               view.link_state.eye_camera_distance_m, view.link_state.stream_text.c_str(),
               view.link_state.insecure ? 1 : 0);
  const bool ok = std::fflush(f) == 0;
  if (std::fclose(f) != 0 || !ok) {
    *error = path + ": cannot write: " + std::strerror(errno);
    return false;
  }
  return true;
}

std::optional<std::vector<LoggedView>> loadLoggedViews(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open";
    return std::nullopt;
  }
  std::vector<LoggedView> views;
  std::string line;
  int number = 0;
  bool with_cues = true, with_insecure = true;
  const auto bad = [&](const std::string& why) {
    *error = path + ":" + std::to_string(number) + ": " + why;
    return std::nullopt;
  };
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number == 1) {
      with_insecure = line == kHeader;
      with_cues = with_insecure || line == kHeaderWithoutInsecure;
      if (!with_cues && line != kHeaderWithoutCues)
        return bad("not a views file (the first line is not '" + std::string(kHeader) + "')");
      continue;
    }
    if (line.empty()) continue;
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string field; std::getline(ss, field, ',');) fields.push_back(field);
    if (with_cues && !with_insecure && fields.size() == 12 && line.back() == ',') fields.emplace_back();  // no stream text
    const std::size_t expected = with_insecure ? 14 : with_cues ? 13 : 9;
    if (fields.size() != expected)
      return bad(std::to_string(expected) + " fields expected, " + std::to_string(fields.size()) + " found");
    LoggedView view;
    view.png = fields[0];
    if (view.png.empty() || view.png.find('/') != std::string::npos || view.png == "." || view.png == "..")
      return bad("'" + view.png + "' is not a file name");
    char* end = nullptr;
    errno = 0;
    const unsigned long long sequence = std::strtoull(fields[1].c_str(), &end, 10);
    if (fields[1].empty() || *end != '\0' || errno != 0 || fields[1][0] == '-')
      return bad("stereo_sequence '" + fields[1] + "' is not a number");
    view.stereo_sequence = sequence;
    double v[7];
    for (int i = 0; i < 7; ++i) {
      const std::string& text = fields[std::size_t(2 + i)];
      v[i] = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(v[i])) return bad("'" + text + "' is not a finite number");
    }
    Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (std::abs(q.norm() - 1.0) > 1e-6) return bad("the quaternion is not of unit length");
    view.T_vr_hmd = Eigen::Isometry3d::Identity();
    view.T_vr_hmd.linear() = q.normalized().toRotationMatrix();
    view.T_vr_hmd.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    if (with_cues) {
      double cue[3];
      for (int i = 0; i < 3; ++i) {
        const std::string& text = fields[std::size_t(9 + i)];
        cue[i] = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(cue[i])) return bad("'" + text + "' is not a finite number");
      }
      if (!(cue[0] >= 0 && cue[0] <= 1)) return bad("image_saturation outside [0, 1]");
      view.image_saturation = static_cast<float>(cue[0]);
      view.link_state.image_age_ms = cue[1];
      view.link_state.eye_camera_distance_m = cue[2];
      view.link_state.stream_text = fields[12];
      if (with_insecure) {
        if (fields[13] != "0" && fields[13] != "1") return bad("insecure_link '" + fields[13] + "' is not 0 or 1");
        view.link_state.insecure = fields[13] == "1";
      }
    }
    views.push_back(std::move(view));
  }
  if (number == 0) {
    *error = path + ": empty (not a views file)";
    return std::nullopt;
  }
  return views;
}

}  // namespace telesphere::xr::frame_loop
