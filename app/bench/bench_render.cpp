// SPDX-License-Identifier: MIT
/// @brief `telesphere-bench render`: the spherical renderer's three paths at headset resolutions
///        (1440×1600 per eye, the paper's Vive Pro Eye; 2064×2208, Quest 3 class) from 4K
///        double-sphere camera images: ms per stereo frame on this machine's GL, the cost against
///        the floor (a full-screen pass of the same size sampling the same 4K texture once per
///        pixel through a homography, i.e. a planar timewarp), and each path's max and mean
///        error against the double-precision reference, in camera pixels.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "shaders/egl_context.h"
#include "shaders/offscreen_target.h"
#include "shaders/shader_program.h"
#include "app/bench/bench_table.h"
#include "app/bench/bench_topic.h"
#include "calib/synthetic/typical_lenses.h"
#include "xr/render/depth_proxy.h"
#include "xr/render/reference_renderer.h"
#include "xr/render/spherical_renderer.h"

namespace telesphere::bench {
namespace {

constexpr int kCamWidth = calib::synthetic::kTypicalSensorWidthPx;    // 3840
constexpr int kCamHeight = calib::synthetic::kTypicalSensorHeightPx;  // 2160

struct EyeSize {
  const char* name;
  int width, height;
};

/// Times each of `variants` `rounds` times, interleaved round by round (so that load from other
/// processes hits all of them alike), after one warm-up run each; median ms per variant. Each
/// variant ends with glFinish.
std::vector<double> interleavedMedianMs(int rounds, const std::vector<std::function<void()>>& variants) {
  for (const auto& v : variants) v();
  std::vector<std::vector<double>> ms(variants.size());
  for (int r = 0; r < rounds; ++r)
    for (std::size_t i = 0; i < variants.size(); ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      variants[i]();
      ms[i].push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  std::vector<double> median;
  for (auto& m : ms) {
    std::sort(m.begin(), m.end());
    median.push_back(m[m.size() / 2]);
  }
  return median;
}

/// An eye of the given size with a headset-like asymmetric field of view and a head that has
/// moved 2.5 cm and turned 0.3 rad away from the camera pose.
xr::render::EyeView eyeView(int width, int height, double side) {
  xr::render::EyeView view;
  view.fov = {side < 0 ? -0.96 : -0.82, side < 0 ? 0.82 : 0.96, 0.9, -0.92};
  view.width = width;
  view.height = height;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.3, 1, 0).normalized()).toRotationMatrix() *
               xr::render::kR_optical_view;
  T.translation() << 0.015 * side, -0.01, 0.015;
  view.T_cam_eye = T;
  return view;
}

/// Window pixel (GL, origin bottom left) → normalised texture coordinate of a pinhole camera with
/// the lens's fx, fy, cx, cy, seen through the eye's rotation.
Eigen::Matrix3d floorHomography(const xr::render::EyeView& view, const calib::GenericCamera& camera) {
  const Eigen::VectorXd p = camera.params();
  const double tl = std::tan(view.fov.angle_left), tr = std::tan(view.fov.angle_right);
  const double td = std::tan(view.fov.angle_down), tu = std::tan(view.fov.angle_up);
  Eigen::Matrix3d ray_from_window, K, texture_from_pixel;
  ray_from_window << (tr - tl) / view.width, 0, tl, 0, (tu - td) / view.height, td, 0, 0, -1;
  K << p[0], 0, p[2], 0, p[1], p[3], 0, 0, 1;
  texture_from_pixel << 1.0 / kCamWidth, 0, 0.5 / kCamWidth, 0, 1.0 / kCamHeight, 0.5 / kCamHeight,
      0, 0, 1;
  return texture_from_pixel * K * view.T_cam_eye.linear() * ray_from_window;
}

std::vector<std::uint8_t> picture(int w, int h) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * w + x) * 3];
      p[0] = std::uint8_t(x * 255 / (w - 1));
      p[1] = std::uint8_t(y * 255 / (h - 1));
      p[2] = ((x / 64 + y / 64) % 2) ? 220 : 30;
    }
  return rgb;
}

/// A room's inverse depth in 4° tiles: a wall 0.5 m ahead, the floor 0.4 m below, the rest 3 m
/// (what the grid proxy's cost is measured on; the cost does not depend on the values).
std::shared_ptr<const xr::render::InverseDepthGrid> roomGrid() {
  auto grid = std::make_shared<xr::render::InverseDepthGrid>(4.0);
  for (int row = 0; row < grid->rows(); ++row)
    for (int col = 0; col < grid->cols(); ++col) {
      const Eigen::Vector3d u = grid->tileCentre(row, col);
      grid->at(row, col) = static_cast<float>(std::max({1.0 / 3.0, u.z() / 0.5, u.y() / 0.4}));
    }
  return grid;
}

nlohmann::json runRender(const BenchContext& ctx) {
  std::string error;
  const auto context = gl::EglContext::createSurfaceless(&error);
  if (!context) throw std::runtime_error("no OpenGL 4.5 context: " + error);
  const calib::GenericCamera camera(calib::DoubleSphereCamera<double>(
      calib::synthetic::TypicalLens<calib::DoubleSphereCamera>::parameters()));
  const int frames = ctx.quick ? 2 : 20;
  std::vector<EyeSize> sizes = {{"1440x1600", 1440, 1600}, {"2064x2208", 2064, 2208}};
  if (ctx.quick) sizes.resize(1);  // CI smoke run: the paper's headset only
  // Errors are measured on the left eye at full size (a quarter of each side under --quick).
  const int error_div = ctx.quick ? 4 : 1;

  // Two cameras (one per eye), each with its own 4K image, as in the real stereo setup.
  const xr::render::SourceImage image = xr::render::SourceImage::rgb8(kCamWidth, kCamHeight, picture(kCamWidth, kCamHeight));
  xr::render::GpuCamera cam_l(camera, kCamWidth, kCamHeight), cam_r(camera, kCamWidth, kCamHeight);
  if (!cam_l.upload(image, &error) || !cam_r.upload(image, &error)) throw std::runtime_error(error);
  const xr::render::SourceImage coordinates = xr::render::SourceImage::pixelCoordinates(kCamWidth, kCamHeight);
  xr::render::GpuCamera cam_coords(camera, kCamWidth, kCamHeight);
  if (!cam_coords.upload(coordinates, &error)) throw std::runtime_error(error);

  auto homography = gl::loadProgram("fullscreen.vert", "homography.frag", {}, &error);
  if (!homography) throw std::runtime_error(error);
  gl::GlVertexArray vao = gl::createVertexArray();
  gl::GlTexture floor_l = gl::createTexture(GL_TEXTURE_2D), floor_r = gl::createTexture(GL_TEXTURE_2D);
  for (GLuint t : {floor_l.id(), floor_r.id()}) {
    glTextureStorage2D(t, 1, GL_RGBA8, kCamWidth, kCamHeight);
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t, 0, 0, 0, kCamWidth, kCamHeight, GL_RGB, GL_UNSIGNED_BYTE, image.bytes.data());
  }

  xr::render::SphericalRenderer renderer;
  Table table({"path", "eye size", "ms / stereo frame", "vs floor", "max err px", "mean err px"});
  nlohmann::json json;
  json["renderer"] = context->renderer();
  json["camera_image"] = {kCamWidth, kCamHeight};
  json["frames"] = frames;

  for (const EyeSize& size : sizes) {
    gl::OffscreenTarget target_l(size.width, size.height), target_r(size.width, size.height);
    const xr::render::EyeView view_l = eyeView(size.width, size.height, -1.0);
    const xr::render::EyeView view_r = eyeView(size.width, size.height, 1.0);

    // The floor: the homography a planar timewarp would apply for this eye if the camera were
    // a pinhole with the lens's focal length and principal point (so it samples the texture at
    // the same scale as the sphere paths): window pixel → eye ray → R_cam_eye → pinhole pixel →
    // texture coordinate.
    const Eigen::Matrix3d H = floorHomography(view_l, camera);
    const GLuint hp = homography->id();
    const Eigen::Matrix3f H_f = H.cast<float>();
    glProgramUniformMatrix3fv(hp, glGetUniformLocation(hp, "u_H"), 1, GL_FALSE, H_f.data());
    std::vector<std::function<void()>> variants;
    variants.push_back([&] {
      glUseProgram(hp);
      glBindVertexArray(vao.id());
      glViewport(0, 0, size.width, size.height);
      glBindTextureUnit(0, floor_l.id());
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target_l.framebuffer());
      glDrawArrays(GL_TRIANGLES, 0, 3);
      glBindTextureUnit(0, floor_r.id());
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target_r.framebuffer());
      glDrawArrays(GL_TRIANGLES, 0, 3);
      glFinish();
      glUseProgram(0);
    });
    // The three paths on the sphere, then the exact path on a 4° inverse-depth grid (#35).
    struct Variant {
      std::string name;
      xr::render::RenderSettings settings;
      double eye_shift_m = 0;  // both eyes moved along the camera's x
      std::string json_key = {};  // the summary figure it gives (render_ms_added_<key>), if any
    };
    std::vector<Variant> paths;
    for (xr::render::RenderPath path : {xr::render::RenderPath::kExact, xr::render::RenderPath::kMesh, xr::render::RenderPath::kLut}) {
      xr::render::RenderSettings settings;
      settings.path = path;
      paths.push_back({std::string(xr::render::renderPathName(path)), settings});
    }
    // The grid proxy: each eye ray marches to its first crossing (default), or takes fixed-point
    // steps from its own direction (no march); the march's steps grow with the eye's distance from
    // the camera, so also with both eyes 6 cm further to the side (a head that moved).
    xr::render::RenderSettings with_grid;
    with_grid.depth_grid = roomGrid();
    paths.push_back({"exact, grid proxy", with_grid, 0.0, "grid"});
    xr::render::RenderSettings no_march = with_grid;
    no_march.grid_march_step_tiles = std::numeric_limits<double>::infinity();
    paths.push_back({"exact, grid, no march", no_march, 0.0, "grid_no_march"});
    paths.push_back({"exact, grid, eyes 6 cm aside", with_grid, 0.06});
    paths.push_back({"exact, grid, no march, 6 cm aside", no_march, 0.06});
    bool ok = true;
    for (const Variant& variant : paths)
      variants.push_back([&, settings = variant.settings, shift = variant.eye_shift_m] {
        xr::render::EyeView l = view_l, r = view_r;
        l.T_cam_eye.translation().x() += shift;
        r.T_cam_eye.translation().x() += shift;
        ok &= renderer.render(cam_l, l, settings, target_l.framebuffer(), &error);
        ok &= renderer.render(cam_r, r, settings, target_r.framebuffer(), &error);
        glFinish();
      });
    const std::vector<double> ms = interleavedMedianMs(frames, variants);
    if (!ok) throw std::runtime_error(error);
    const double floor_ms = ms[0];
    table.addRow({"floor (homography)", size.name, formatNumber(floor_ms), "1", "-", "-"});
    json["sizes"][size.name]["floor_ms"] = floor_ms;

    for (std::size_t k = 0; k < paths.size(); ++k) {
      const xr::render::RenderPath path = paths[k].settings.path;
      const bool grid = paths[k].settings.depth_grid != nullptr;
      // Accuracy: the projection map of the left eye against the reference.
      xr::render::EyeView err_view = eyeView(size.width / error_div, size.height / error_div, -1.0);
      err_view.T_cam_eye.translation().x() += paths[k].eye_shift_m;
      xr::render::RenderSettings err_settings = paths[k].settings;
      err_settings.border_rgba = {-1.0f, -1.0f, -1.0f, 0.0f};
      gl::OffscreenTarget map(err_view.width, err_view.height, GL_RGBA32F);
      if (!renderer.render(cam_coords, err_view, err_settings, map.framebuffer(), &error))
        throw std::runtime_error(error);
      const xr::render::ProjectionMapError e =
          xr::render::compareProjectionMap(map.readRgbaF(), camera, coordinates, err_view, err_settings);

      const std::string name = paths[k].name;
      const double path_ms = ms[k + 1];
      table.addRow({name, size.name, formatNumber(path_ms), formatNumber(path_ms / floor_ms),
                    formatNumber(e.max_px, 2), formatNumber(e.mean_px, 2)});
      json["sizes"][size.name][name] = {{"ms", path_ms},
                                        {"cost_vs_warp", path_ms / floor_ms},
                                        {"max_error_px", e.max_px},
                                        {"mean_error_px", e.mean_px},
                                        {"validity_mismatch_pixels", e.validity_mismatch}};
      if (size.width == 1440 && path == xr::render::RenderPath::kExact && !grid) {
        json["exact_max_error_px"] = e.max_px;
        json["exact_cost_vs_warp"] = path_ms / floor_ms;
      }
      if (size.width == 1440 && !paths[k].json_key.empty())  // against the exact path on the sphere
        json["render_ms_added_" + paths[k].json_key] = path_ms - ms[1];
      if (size.width == 1440 && paths[k].json_key == "grid") json["grid_max_error_px"] = e.max_px;
    }
  }
  ctx.out << "Spherical renderer on " << context->renderer() << ", 2 x " << kCamWidth << "x"
          << kCamHeight << " RGB camera images (double sphere), r = 1 m, median of " << frames
          << " stereo frames (paths and floor interleaved); errors vs the double reference over the left eye"
          << (ctx.quick ? " at 1/4 size" : "") << " (mesh 96x192, LUT 1024^2; the grid proxy: 4 deg tiles, a room from 0.4 m, "
          << "march steps of " << xr::render::kGridMarchStepTiles << " tile, " << xr::render::kGridProxySteps
          << " bisections; without the march " << xr::render::kGridProxySteps << " fixed-point steps):\n";
  table.print(ctx.out);
  return json;
}

}  // namespace
}  // namespace telesphere::bench

TELESPHERE_BENCH_TOPIC(render, telesphere::bench::BenchTopic{
                                   "render",
                                   "spherical renderer: ms per stereo frame per path vs a "
                                   "homography warp, and error vs the double reference",
                                   {},
                                   telesphere::bench::runRender});
