// SPDX-License-Identifier: MIT
/// @brief The synthetic cameras' scene (see synthetic_scene.h).
#include "robot/cameras/synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "calib/debug_assert.h"

namespace telesphere::robot::cameras {
namespace {

/// A well-mixed 64-bit hash of a pattern cell (murmur3's finaliser), as a value in [0, 1).
float sceneCellHash(std::int64_t cx, std::int64_t cy, std::uint64_t octave, std::uint32_t seed) {
  std::uint64_t h = static_cast<std::uint64_t>(cx) * 0x9E3779B97F4A7C15ULL;
  h ^= static_cast<std::uint64_t>(cy) * 0xC2B2AE3D27D4EB4FULL;
  h ^= (octave + 1) * 0x165667B19E3779F9ULL + seed;
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDULL;
  h ^= h >> 33;
  h *= 0xC4CEB9FE1A85EC53ULL;
  h ^= h >> 33;
  return static_cast<float>(h >> 40) * (1.0F / 16777216.0F);
}

/// The multi-scale pattern: blocks of 4^k / 256 m (k = 0…4, i.e. 3.9 mm … 1 m), each block
/// darkening by a hashed 0…20 %. Cells come from one integer grid by arithmetic shifts.
float scenePatternFactor(double x, double y, std::uint32_t seed) {
  constexpr double kFinest = 256.0;  // cells per metre of the finest octave
  const double fx = std::floor(x * kFinest), fy = std::floor(y * kFinest);
  if (!(std::abs(fx) < 1e15 && std::abs(fy) < 1e15)) return 1.0F;
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  float factor = 1.0F;
  for (int k = 0; k < 5; ++k) {
    const int shift = 2 * k;
    factor *= 1.0F - 0.2F * sceneCellHash(ix >> shift, iy >> shift, static_cast<std::uint64_t>(k), seed);
  }
  return factor;
}

Eigen::Vector3f sceneSurfaceColour(const SurfaceStyle& style, double x, double y) {
  return style.pattern ? Eigen::Vector3f(style.rgb * scenePatternFactor(x, y, style.seed)) : style.rgb;
}

/// Shade of a box face by its axis (0 x, 1 y, 2 z): makes box edges visible without lighting.
constexpr float kBoxFaceShade[3] = {0.85F, 0.7F, 1.0F};

}  // namespace

PoseAtTime fixedPose(const Eigen::Isometry3d& T_world_object) {
  return [T_world_object](std::int64_t) { return T_world_object; };
}

int SyntheticScene::addRoom(const std::string& name, const Eigen::Isometry3d& T_world_room,
                            const Eigen::Vector3d& half_extents, const SurfaceStyle& walls_x,
                            const SurfaceStyle& walls_y, const SurfaceStyle& floor,
                            const SurfaceStyle& ceiling) {
  TS_ASSERT((half_extents.array() > 0.0).all(), half_extents.transpose());
  SceneObject o;
  o.name = name;
  o.kind = SceneObjectKind::kRoom;
  o.T_world_object = fixedPose(T_world_room);
  o.half_extents = half_extents;
  o.faces = {walls_x, walls_x, walls_y, walls_y, floor, ceiling};
  objects_.push_back(std::move(o));
  return static_cast<int>(objects_.size()) - 1;
}

int SyntheticScene::addBox(const std::string& name, PoseAtTime T_world_box,
                           const Eigen::Vector3d& half_extents, const SurfaceStyle& style) {
  TS_ASSERT((half_extents.array() > 0.0).all(), half_extents.transpose());
  SceneObject o;
  o.name = name;
  o.kind = SceneObjectKind::kBox;
  o.T_world_object = std::move(T_world_box);
  o.half_extents = half_extents;
  for (int f = 0; f < 6; ++f) {
    o.faces[static_cast<std::size_t>(f)] = style;
    o.faces[static_cast<std::size_t>(f)].rgb *= kBoxFaceShade[f / 2];
  }
  objects_.push_back(std::move(o));
  return static_cast<int>(objects_.size()) - 1;
}

int SyntheticScene::addPlanarTarget(const std::string& name, PoseAtTime T_world_target,
                                    calib::TargetTexture texture, const Eigen::AlignedBox2d& extent) {
  TS_ASSERT(!extent.isEmpty(), extent.min().transpose(), extent.max().transpose());
  SceneObject o;
  o.name = name;
  o.kind = SceneObjectKind::kPlanarTarget;
  o.T_world_object = std::move(T_world_target);
  o.texture = std::move(texture);
  o.extent = extent;
  objects_.push_back(std::move(o));
  return static_cast<int>(objects_.size()) - 1;
}

int SyntheticScene::addAprilGrid(const std::string& name, PoseAtTime T_world_board,
                                 const calib::AprilGrid& grid) {
  const double m = grid.tag_size;  // the paper margin of calib::aprilGridTexture
  return addPlanarTarget(name, std::move(T_world_board), calib::aprilGridTexture(grid),
                         Eigen::AlignedBox2d(Eigen::Vector2d(-m, -m),
                                             Eigen::Vector2d(grid.width() + m, grid.height() + m)));
}

int SyntheticScene::addArucoMarker(const std::string& name, PoseAtTime T_world_marker,
                                   const std::string& dictionary, int id, double size) {
  return addPlanarTarget(name, std::move(T_world_marker),
                         calib::arucoMarkerTexture(dictionary, id, size),
                         Eigen::AlignedBox2d(Eigen::Vector2d(-size, -size), Eigen::Vector2d(size, size)));
}

int SyntheticScene::find(const std::string& name) const {
  for (std::size_t i = 0; i < objects_.size(); ++i)
    if (objects_[i].name == name) return static_cast<int>(i);
  return -1;
}

SceneView SyntheticScene::view(std::int64_t t_ns, const Eigen::Isometry3d& T_world_cam) const {
  SceneView view;
  view.placed_.reserve(objects_.size());
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  for (const SceneObject& object : objects_) {
    const Eigen::Isometry3d T_world_object = object.T_world_object(t_ns);
    const Eigen::Isometry3d T_object_cam = T_world_object.inverse() * T_world_cam;
    SceneView::Placed p;
    p.object = &object;
    p.R_object_cam = T_object_cam.linear();
    p.p_object_cam = T_object_cam.translation();
    if (object.kind != SceneObjectKind::kRoom) {
      // Bounding sphere of the object: rays outside its cone are rejected by one dot product.
      Eigen::Vector3d centre_object = Eigen::Vector3d::Zero();
      double radius = object.half_extents.norm();
      if (object.kind == SceneObjectKind::kPlanarTarget) {
        centre_object.head<2>() = object.extent.center();
        radius = 0.5 * object.extent.sizes().norm();
      }
      const Eigen::Vector3d c_cam = T_cam_world * (T_world_object * centre_object);
      const double distance = c_cam.norm();
      if (distance > radius * (1.0 + 1e-9) + 1e-12) {
        p.c_cam_unit = c_cam / distance;
        const double s = radius / distance;
        p.cos_cull = std::sqrt(std::max(0.0, 1.0 - s * s)) - 1e-9;
      }
    }
    view.placed_.push_back(p);
  }
  return view;
}

bool SceneView::intersect(const Eigen::Vector3d& d_cam, SceneHit* out_hit) const {
  double best_t = std::numeric_limits<double>::infinity();
  int best = -1, best_face = -1;
  Eigen::Vector2d best_uv = Eigen::Vector2d::Zero();
  float best_grey = 0.0F;
  for (std::size_t i = 0; i < placed_.size(); ++i) {
    const Placed& p = placed_[i];
    if (p.cos_cull > -2.0 && d_cam.dot(p.c_cam_unit) < p.cos_cull) continue;
    const SceneObject& object = *p.object;
    const Eigen::Vector3d d = p.R_object_cam * d_cam;
    const Eigen::Vector3d& o = p.p_object_cam;
    switch (object.kind) {
      case SceneObjectKind::kRoom: {
        // From inside: the exit through the nearest wall.
        if ((o.array().abs() > object.half_extents.array()).any()) break;
        double t_exit = std::numeric_limits<double>::infinity();
        int face = -1;
        for (int a = 0; a < 3; ++a) {
          if (d[a] == 0.0) continue;
          const double wall = d[a] > 0.0 ? object.half_extents[a] : -object.half_extents[a];
          const double t = (wall - o[a]) / d[a];
          if (t < t_exit) {
            t_exit = t;
            face = 2 * a + (d[a] > 0.0 ? 1 : 0);
          }
        }
        if (face >= 0 && t_exit > 0.0 && t_exit < best_t) {
          const Eigen::Vector3d q = o + t_exit * d;
          const int a = face / 2;
          best_t = t_exit;
          best = static_cast<int>(i);
          best_face = face;
          best_uv = Eigen::Vector2d(q[(a + 1) % 3], q[(a + 2) % 3]);
        }
        break;
      }
      case SceneObjectKind::kBox: {
        // Slab test from outside; the entry face is the one hit.
        double t_near = -std::numeric_limits<double>::infinity();
        double t_far = std::numeric_limits<double>::infinity();
        int face = -1;
        bool miss = false;
        for (int a = 0; a < 3 && !miss; ++a) {
          const double h = object.half_extents[a];
          if (d[a] == 0.0) {
            miss = std::abs(o[a]) > h;
            continue;
          }
          const double inv = 1.0 / d[a];
          const double t1 = (-h - o[a]) * inv, t2 = (h - o[a]) * inv;
          const double tn = std::min(t1, t2), tf = std::max(t1, t2);
          if (tn > t_near) {
            t_near = tn;
            face = 2 * a + (d[a] > 0.0 ? 0 : 1);
          }
          t_far = std::min(t_far, tf);
        }
        if (miss || face < 0 || t_near > t_far || t_near <= 0.0 || t_near >= best_t) break;
        const Eigen::Vector3d q = o + t_near * d;
        const int a = face / 2;
        best_t = t_near;
        best = static_cast<int>(i);
        best_face = face;
        best_uv = Eigen::Vector2d(q[(a + 1) % 3], q[(a + 2) % 3]);
        break;
      }
      case SceneObjectKind::kPlanarTarget: {
        if (d.z() == 0.0) break;
        const double t = -o.z() / d.z();
        if (!(t > 0.0) || t >= best_t) break;
        const Eigen::Vector2d xy(o.x() + t * d.x(), o.y() + t * d.y());
        if (!object.extent.contains(xy)) break;
        const int value = object.texture(xy.x(), xy.y());
        if (value < 0) break;
        best_t = t;
        best = static_cast<int>(i);
        best_face = -1;
        best_grey = o.z() > 0.0 ? static_cast<float>(value) : 180.0F;  // printed on +z
        break;
      }
    }
  }
  if (best < 0) return false;
  out_hit->distance = best_t;
  out_hit->object = best;
  const SceneObject& object = *placed_[static_cast<std::size_t>(best)].object;
  if (object.kind == SceneObjectKind::kPlanarTarget) {
    out_hit->rgb.setConstant(best_grey);
  } else {
    out_hit->rgb = sceneSurfaceColour(object.faces[static_cast<std::size_t>(best_face)], best_uv.x(),
                                      best_uv.y());
  }
  return true;
}

Eigen::Isometry3d DefaultSceneLayout::T_robot_marker_centre() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // Marker z (out of the print) along −x of the robot, towards the head; marker x along −y
  // (the head's right), marker y up.
  T.linear().col(0) = -Eigen::Vector3d::UnitY();
  T.linear().col(1) = Eigen::Vector3d::UnitZ();
  T.linear().col(2) = -Eigen::Vector3d::UnitX();
  T.translation() = Eigen::Vector3d(1.0, 0.40, 0.60);
  return T;
}

Eigen::Isometry3d DefaultSceneLayout::T_robot_marker(std::int64_t t_ns) {
  constexpr double kPeriod = 4.0, kRadius = 0.08;
  const double phase = 2.0 * M_PI * std::fmod(static_cast<double>(t_ns) * 1e-9, kPeriod) / kPeriod;
  Eigen::Isometry3d T = T_robot_marker_centre();
  T.translation() += Eigen::Vector3d(0.0, kRadius * std::cos(phase), kRadius * std::sin(phase));
  return T;
}

Eigen::Isometry3d DefaultSceneLayout::T_robot_board() const {
  // Board centre 1.1 m ahead of the head and 0.45 m to its right, face turned towards the head.
  const Eigen::Vector3d centre = head_position + Eigen::Vector3d(1.1, -0.45, 0.10);
  const Eigen::Vector3d z_board = (head_position - centre).normalized();
  Eigen::Vector3d x_board = Eigen::Vector3d::UnitZ().cross(z_board).normalized();  // level
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x_board;
  T.linear().col(1) = z_board.cross(x_board);
  T.linear().col(2) = z_board;
  T.translation() = centre - T.linear() * Eigen::Vector3d(grid.width() / 2, grid.height() / 2, 0.0);
  return T;
}

SyntheticScene defaultScene(const DefaultSceneLayout& layout) {
  SyntheticScene scene;
  const auto at = [](double x, double y, double z) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(x, y, z);
    return T;
  };
  const auto style = [](float r, float g, float b, std::uint32_t seed) {
    return SurfaceStyle{Eigen::Vector3f(r, g, b), true, seed};
  };
  // Room x ∈ [−2, 4], y ∈ [−2.5, 2.5], z ∈ [−0.8, 2.0] around the robot base.
  scene.addRoom("room", at(1.0, 0.0, 0.6), Eigen::Vector3d(3.0, 2.5, 1.4), style(205, 185, 150, 11),
                style(160, 180, 205, 12), style(140, 110, 80, 13), style(235, 235, 228, 14));
  const Eigen::Vector3d& h = layout.head_position;
  // Front faces 1.0 m and 2.0 m ahead of the head.
  scene.addBox("box_1m", fixedPose(at(h.x() + 1.0 + 0.15, 0.10, 0.20)), Eigen::Vector3d(0.15, 0.15, 0.15),
               style(210, 60, 50, 21));
  scene.addBox("box_2m", fixedPose(at(h.x() + 2.0 + 0.25, 0.65, 0.10)), Eigen::Vector3d(0.25, 0.30, 0.50),
               style(60, 170, 80, 22));
  const auto aside = [&](double angle_deg, double distance) {
    const double a = angle_deg * M_PI / 180.0;
    return at(h.x() + distance * std::cos(a), h.y() + distance * std::sin(a), h.z());
  };
  scene.addBox("box_left", fixedPose(aside(70.0, 0.9)), Eigen::Vector3d(0.12, 0.12, 0.12),
               style(60, 90, 210, 23));
  scene.addBox("box_behind", fixedPose(aside(95.0, 1.2)), Eigen::Vector3d(0.12, 0.12, 0.12),
               style(230, 200, 40, 24));
  scene.addAprilGrid("board", fixedPose(layout.T_robot_board()), layout.grid);
  // The wrist: a small grey box just behind the marker, moving with it.
  const PoseAtTime marker_pose = layout.marker_pose ? layout.marker_pose : PoseAtTime(&DefaultSceneLayout::T_robot_marker);
  scene.addBox("wrist",
               [marker_pose](std::int64_t t_ns) { return marker_pose(t_ns) * Eigen::Translation3d(0, 0, -0.045); },
               Eigen::Vector3d(0.06, 0.06, 0.04), SurfaceStyle{Eigen::Vector3f(120, 120, 125), false, 0});
  scene.addArucoMarker("marker", marker_pose, layout.marker_dictionary, layout.marker_id, layout.marker_size);
  return scene;
}

}  // namespace telesphere::robot::cameras
