// SPDX-License-Identifier: MIT
/// @brief ProjectionMapRecorder (see projection_map_recorder.h).
#include "xr/frame_loop/projection_map_recorder.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <vector>

#include "robot/link/link_pose.h"
#include "robot/link/pose_csv.h"

namespace telesphere::xr::frame_loop {
std::unique_ptr<ProjectionMapRecorder> ProjectionMapRecorder::open(const std::string& dir, int eye_width,
                                                                   int eye_height, std::string* error) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::ofstream csv(dir + "/frames.csv", std::ios::trunc);
  if (ec || !csv) {
    *error = "cannot write the projection maps to " + dir + ": " + (ec ? ec.message() : std::strerror(errno));
    return nullptr;
  }
  csv.precision(17);
  csv << "index,display_ns,stereo_sequence,capture_ns,mode,radius_m,ipd_m,fov_left,fov_right,fov_up,"
         "fov_down,width,height,image_width,image_height";
  for (const char* pose : {"hmd", "robot_vr", "cam_left", "cam_right"}) csv << link::poseCsvHeader(pose);
  csv << '\n';
  auto recorder = std::unique_ptr<ProjectionMapRecorder>(
      new ProjectionMapRecorder(dir, std::move(csv), eye_width, eye_height));
  if (!recorder->target_.complete()) {
    *error = "cannot create a float render target for the projection maps";
    return nullptr;
  }
  return recorder;
}

ProjectionMapRecorder::ProjectionMapRecorder(std::string dir, std::ofstream csv, int width, int height)
    : dir_(std::move(dir)), csv_(std::move(csv)), target_(width, height, GL_RGBA32F) {}

bool ProjectionMapRecorder::record(OperatorView& view, std::int64_t display_ns, const Eigen::Isometry3d& T_vr_hmd,
                                   const Eigen::Isometry3d T_hmd_eye[2], double ipd, const render::EyeView& eye,
                                   std::string* error) {
  const auto& frame = view.frame();
  if (!frame) return true;
  const std::size_t pixels = static_cast<std::size_t>(eye.width) * eye.height;
  std::vector<float> maps(2 * pixels * 2, std::numeric_limits<float>::quiet_NaN());
  for (int e = 0; e < 2; ++e) {
    if (!view.renderProjectionMap(e, T_vr_hmd * T_hmd_eye[e], eye, target_.framebuffer(), error)) return false;
    const std::vector<float> rgba = target_.readRgbaF();
    for (std::size_t i = 0; i < pixels; ++i) {
      if (!(rgba[i * 4 + 3] > 0.5f)) continue;
      maps[(e * pixels + i) * 2] = rgba[i * 4];
      maps[(e * pixels + i) * 2 + 1] = rgba[i * 4 + 1];
    }
  }
  ++index_;
  const std::string map_path = dir_ + "/map_" + std::to_string(index_) + ".f32";
  std::ofstream map(map_path, std::ios::binary | std::ios::trunc);
  map.write(reinterpret_cast<const char*>(maps.data()), static_cast<std::streamsize>(maps.size() * sizeof(float)));
  if (!map) {
    *error = "cannot write " + map_path;
    return false;
  }
  const render::RenderSettings& s = view.settings();
  csv_ << index_ << ',' << display_ns << ',' << frame->frame.sequence() << ',' << frame->frame.stamps().capture_ns()
       << ',' << link::visualModeName(s.mode) << ',' << s.radius << ',' << ipd << ',' << eye.fov.angle_left << ','
       << eye.fov.angle_right << ',' << eye.fov.angle_up << ',' << eye.fov.angle_down << ',' << eye.width << ','
       << eye.height << ',' << (frame->left ? frame->left->width : 0) << ','
       << (frame->left ? frame->left->height : 0);
  link::writePoseCsv(csv_, T_vr_hmd);
  link::writePoseCsv(csv_, view.T_robot_vr());
  link::writePoseCsv(csv_, link::fromLinkPose(frame->frame.left().t_robot_cam()));
  link::writePoseCsv(csv_, link::fromLinkPose(frame->frame.right().t_robot_cam()));
  csv_ << '\n';
  csv_.flush();
  if (!csv_) {
    *error = "cannot write " + dir_ + "/frames.csv";
    return false;
  }
  return true;
}

}  // namespace telesphere::xr::frame_loop
