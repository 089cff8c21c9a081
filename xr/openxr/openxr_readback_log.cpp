// SPDX-License-Identifier: MIT
#include "xr/openxr/openxr_readback_log.h"

#include <cstdio>
#include <filesystem>
#include <iomanip>

#include "robot/link/visual_mode.h"
#include "shaders/framebuffer_readback.h"
#include "shaders/png_io.h"
#include "xr/render/yuv_planes_file.h"

namespace telesphere::xr::openxr {

std::unique_ptr<OpenXrReadbackLog> OpenXrReadbackLog::open(const std::string& folder, std::string* error) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) {
    *error = folder + ": cannot create the folder: " + ec.message();
    return nullptr;
  }
  std::unique_ptr<OpenXrReadbackLog> log(new OpenXrReadbackLog(folder));
  log->poses_.open(folder + "/poses.csv");
  if (!log->poses_) {
    *error = folder + "/poses.csv: cannot write";
    return nullptr;
  }
  log->poses_ << "session,frame,eye,predicted_display_time_ns,tx,ty,tz,qx,qy,qz,qw,"
                 "angle_left,angle_right,angle_up,angle_down,width,height,srgb_swapchain,png,"
                 "sequence,mode,radius,image_saturation,link_age_ms,eye_camera_distance_m,stream_text\n";
  log->poses_ << std::setprecision(17);
  return log;
}

std::string OpenXrReadbackLog::imageName(const OpenXrEye& eye) const {
  char name[64];
  std::snprintf(name, sizeof name, "s%d_frame%05llu_eye%d.png", session_,
                static_cast<unsigned long long>(eye.frame_index), eye.eye);
  return name;
}

bool OpenXrReadbackLog::eyeDrawn(const OpenXrEye& eye, const frame_loop::OperatorScene& scene, const frame_loop::OperatorView* view,
                                 const render::RenderSettings& settings, std::string* error) {
  std::uint64_t sequence = 0;
  if (view && view->frame()) {
    const auto& frame = view->frame();
    sequence = frame->frame.sequence();
    if (saved_planes_.insert({sequence, eye.eye}).second) {
      char name[80];
      std::snprintf(name, sizeof name, "/planes_%06llu_eye%d.yuv", static_cast<unsigned long long>(sequence), eye.eye);
      if (!render::writeYuvPlanes(folder_ + name, *(eye.eye == 0 ? frame->left : frame->right), error)) return false;
    }
  }
  const Eigen::Isometry3d T_cam_eye = scene.T_cam_eye(eye.eye, eye.T_vr_eye).value_or(Eigen::Isometry3d::Identity());
  const Eigen::Quaterniond q(T_cam_eye.linear());
  const Eigen::Vector3d t = T_cam_eye.translation();
  poses_ << session_ << "," << eye.frame_index << "," << eye.eye << "," << eye.predicted_display_time_ns << ","
         << t.x() << "," << t.y() << "," << t.z() << "," << q.x() << "," << q.y() << "," << q.z() << "," << q.w()
         << "," << eye.fov.angle_left << "," << eye.fov.angle_right << "," << eye.fov.angle_up << ","
         << eye.fov.angle_down << "," << eye.width << "," << eye.height << "," << (eye.srgb_swapchain ? 1 : 0)
         << "," << imageName(eye) << "," << sequence << "," << link::visualModeName(settings.mode) << ","
         << settings.radius << "," << settings.image_saturation << "," << (view ? view->linkState().image_age_ms : -1.0)
         << "," << (view ? view->linkState().eye_camera_distance_m : -1.0) << ","
         << (view ? view->linkState().stream_text : std::string()) << "\n";
  if (!poses_) {
    *error = folder_ + "/poses.csv: write failed";
    return false;
  }
  return true;
}

bool OpenXrReadbackLog::saveImage(const OpenXrEye& eye, std::string* error) const {
  const auto pixels = gl::readFramebufferRgba8(eye.framebuffer, GL_COLOR_ATTACHMENT0, eye.width, eye.height);
  return gl::writePng(folder_ + "/" + imageName(eye), eye.width, eye.height, 4, pixels.data(), error);
}

}  // namespace telesphere::xr::openxr
