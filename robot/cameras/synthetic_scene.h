// SPDX-License-Identifier: MIT
/// @brief The textured 3-D scene the synthetic cameras see (DESIGN.md §4): a room (the inside of
///        a box: walls, floor, ceiling) with a procedural texture that has structure at every
///        scale from 1 m down to 4 mm, boxes at known poses, and planar targets (kalibr's
///        Aprilgrid, the ArUco marker on the manipulator's wrist) whose poses may be functions
///        of time. Unlit: a surface's colour is its texture; box faces get a fixed shade per face
///        (1.0 for ±z, 0.85 for ±x, 0.7 for ±y of the box) so that edges stay visible.
///
/// Use: `SceneView view = scene.view(t_ns, T_world_cam)` freezes the moving parts at t_ns and
/// expresses every object in the camera frame once; `view.intersect(d_cam, &hit)` then gives the
/// nearest surface along the ray from the camera centre (thread-safe, no allocation).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "calib/aprilgrid.h"
#include "calib/target_render.h"

namespace telesphere::robot::cameras {

/// Pose of an object in the world at host time t_ns; must be callable from several threads.
using PoseAtTime = std::function<Eigen::Isometry3d(std::int64_t t_ns)>;

/// A constant pose as a PoseAtTime.
PoseAtTime fixedPose(const Eigen::Isometry3d& T_world_object);

/// Colour of a room or box surface: `rgb` (0…255), modulated by the multi-scale pattern when
/// `pattern` is set (blocks of 1 m, 25 cm, 6.25 cm, 1.6 cm and 3.9 mm, each darkening by up to
/// 20 %, positions in metres of the object's frame), uniform otherwise.
struct SurfaceStyle {
  Eigen::Vector3f rgb{200.0F, 200.0F, 200.0F};
  bool pattern = true;
  std::uint32_t seed = 1;  ///< varies the pattern between surfaces
};

enum class SceneObjectKind { kRoom, kBox, kPlanarTarget };

/// One object. Boxes and the room are centred on their frame's origin with half extents
/// `half_extents` along its axes; a planar target is the plane z = 0 of its frame, printed on
/// the +z side (seen from −z it shows the plain back of the paper, grey 180) and covering at most
/// `extent` (x, y metres) where `texture` is not negative.
struct SceneObject {
  std::string name;
  SceneObjectKind kind = SceneObjectKind::kBox;
  PoseAtTime T_world_object;
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  ///< room and boxes, metres
  std::array<SurfaceStyle, 6> faces;  ///< room and boxes: faces −x, +x, −y, +y, −z, +z
  calib::TargetTexture texture;                            ///< planar targets (grey 0…255)
  Eigen::AlignedBox2d extent;                              ///< planar targets, metres
};

/// Where a ray met the scene.
struct SceneHit {
  double distance = std::numeric_limits<double>::infinity();  ///< along the unit ray, metres
  int object = -1;                                            ///< index into scene.objects()
  Eigen::Vector3f rgb = Eigen::Vector3f::Zero();              ///< 0…255
};

class SyntheticScene;

/// The scene at one instant seen from one camera pose; cheap to build (one per frame), holds a
/// pointer to the scene, which must outlive it.
class SceneView {
 public:
  /// Nearest surface along the ray from the camera centre in unit direction d_cam (camera
  /// frame); false when nothing is hit (a camera outside the room may see nothing).
  bool intersect(const Eigen::Vector3d& d_cam, SceneHit* out_hit) const;

 private:
  friend class SyntheticScene;
  struct Placed {
    Eigen::Matrix3d R_object_cam;
    Eigen::Vector3d p_object_cam;  ///< the camera centre in the object's frame
    Eigen::Vector3d c_cam_unit;    ///< direction to the bounding sphere's centre (culling)
    double cos_cull = -2.0;        ///< rays with d·c_cam_unit below this miss the object
    const SceneObject* object = nullptr;
  };
  std::vector<Placed> placed_;
};

class SyntheticScene {
 public:
  /// The room: the inside of a box at T_world_room with half extents (metres); x faces use
  /// `walls_x`, y faces `walls_y`, the −z face `floor` and the +z face `ceiling`.
  int addRoom(const std::string& name, const Eigen::Isometry3d& T_world_room,
              const Eigen::Vector3d& half_extents, const SurfaceStyle& walls_x,
              const SurfaceStyle& walls_y, const SurfaceStyle& floor, const SurfaceStyle& ceiling);
  /// A solid box centred at its frame's origin.
  int addBox(const std::string& name, PoseAtTime T_world_box, const Eigen::Vector3d& half_extents,
             const SurfaceStyle& style);
  /// A planar target (see SceneObject); `extent` must contain every point where texture ≥ 0.
  int addPlanarTarget(const std::string& name, PoseAtTime T_world_target,
                      calib::TargetTexture texture, const Eigen::AlignedBox2d& extent);
  /// kalibr's Aprilgrid (calib::aprilGridTexture) in its board frame (calib/aprilgrid.h).
  int addAprilGrid(const std::string& name, PoseAtTime T_world_board, const calib::AprilGrid& grid);
  /// An ArUco marker (calib::arucoMarkerTexture) of edge `size` metres centred in its frame.
  int addArucoMarker(const std::string& name, PoseAtTime T_world_marker,
                     const std::string& dictionary, int id, double size);

  const std::vector<SceneObject>& objects() const { return objects_; }
  /// Index of the object called `name`, −1 when there is none.
  int find(const std::string& name) const;

  /// Freezes the scene at host time t_ns for a camera at T_world_cam (optical frame).
  SceneView view(std::int64_t t_ns, const Eigen::Isometry3d& T_world_cam) const;

 private:
  std::vector<SceneObject> objects_;
};

/// The layout of defaultScene() in the `robot` frame (x forward, z up, metres): what tests and
/// the demo need to know about it.
struct DefaultSceneLayout {
  /// Where the demo's head looks from: HeadControllerConfig::defaultNominal() (0.40, 0, 0.45).
  Eigen::Vector3d head_position{0.40, 0.0, 0.45};
  calib::AprilGrid grid{6, 6, 0.088, 0.3};
  std::string marker_dictionary = "DICT_4X4_50";
  int marker_id = 0;
  double marker_size = 0.1;  ///< metres
  /// The wrist marker circles (radius 8 cm, period 4 s) 0.6 m ahead of the head, facing it.
  static Eigen::Isometry3d T_robot_marker(std::int64_t t_ns);
  /// The centre of that circle, with the marker's orientation.
  static Eigen::Isometry3d T_robot_marker_centre();
  /// Where the marker really is (e.g. on a SimulatedManipulator); empty: the circle above.
  PoseAtTime marker_pose;
  /// The Aprilgrid board: 1.1 m ahead and 0.45 m to the right of the head, turned towards it.
  Eigen::Isometry3d T_robot_board() const;
};

/// The demo's default scene (robot frame): a 6 × 5 × 2.8 m room around the robot (floor 0.8 m
/// below the base); boxes whose front faces are 1.0 m ("box_1m") and 2.0 m ("box_2m") ahead of
/// the head, one 0.9 m away 70° to the left ("box_left") and one 1.2 m away 95° to the left
/// ("box_behind", seen only by a lens wider than 180°; the 4K rig sees ±98.8° across); the Aprilgrid ("board"); the wrist marker
/// ("marker") on a small grey wrist box ("wrist"); "room". Exact poses: objects().
SyntheticScene defaultScene(const DefaultSceneLayout& layout = {});

}  // namespace telesphere::robot::cameras
