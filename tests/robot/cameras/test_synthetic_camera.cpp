// SPDX-License-Identifier: MIT
/// @brief The synthetic camera against the double-precision camera model: box edges where
///        model.project puts them (on axis and beyond 90° off axis), an Aprilgrid that calib's
///        detector finds with the true board pose, the pose at capture time, and the threaded
///        CameraSource on a simulated clock.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>

#include "calib/bearing_pose.h"
#include "calib/target_detection.h"
#include "robot/clock/sim_clock.h"
#include "robot/cameras/synthetic_camera.h"
#include "robot/cameras/synthetic_scene.h"
#include "calib/synthetic/calibration_sessions.h"
#include "tests/eventually.h"

namespace telesphere::robot {
namespace {

/// The paper's >180° double-sphere lens scaled to 640×512: ±97° across the width, up to the
/// model's 125° along the diagonals.
calib::GenericCamera lens640() {
  Eigen::VectorXd p(6);
  p << 157.5, 157.8, 319.5, 255.5, -0.18, 0.59;
  return *calib::GenericCamera::create("ds", p);
}

const Eigen::Vector3f kFaceRgb(230.0F, 30.0F, 30.0F);
const Eigen::Vector3f kRoomRgb(40.0F, 40.0F, 40.0F);

/// A pose whose z axis points along the direction at angle theta off the camera's optical axis
/// (azimuth phi), `distance` metres away: a box there shows the camera only its −z face.
Eigen::Isometry3d facingPose(double theta, double phi, double distance) {
  const Eigen::Vector3d dir(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(dir);
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = dir.cross(x);
  T.linear().col(2) = dir;
  T.translation() = distance * dir;
  return T;
}

Eigen::Isometry3d someCameraPose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() << 0.3, -0.2, 0.1;
  return T;
}

/// A uniform grey room (half extent 6 m) around the world origin.
void addPlainRoom(cameras::SyntheticScene& scene) {
  const cameras::SurfaceStyle plain{kRoomRgb, false, 0};
  scene.addRoom("room", Eigen::Isometry3d::Identity(), Eigen::Vector3d(6, 6, 6), plain, plain, plain, plain);
}

struct EdgeCheck {
  int measured = 0;
  double max_error_px = 0.0;
};

/// Measures where the silhouette of the −z face of box `T_cam_box` (half extents h, uniform
/// kFaceRgb on kRoomRgb) crosses image rows (near-vertical edges) or columns (near-horizontal
/// ones) next to 3 points on each of its 4 edges: coverage summed across the edge (the renderer
/// samples n×n per pixel), against the crossing of the model's projection of the 3-D edge.
EdgeCheck checkBoxEdges(const cameras::CameraFrame& frame, const calib::GenericCamera& camera,
                        const Eigen::Isometry3d& T_cam_box, const Eigen::Vector3d& h) {
  const auto& px = *frame.pixels;
  const auto coverage = [&](int u, int v) {
    const double red = px[(static_cast<std::size_t>(v) * frame.width + u) * 3];
    return (red - kRoomRgb.x()) / (kFaceRgb.x() - kRoomRgb.x());
  };
  const Eigen::Vector3d corners[4] = {{-h.x(), -h.y(), -h.z()}, {h.x(), -h.y(), -h.z()},
                                      {h.x(), h.y(), -h.z()}, {-h.x(), h.y(), -h.z()}};
  const Eigen::Vector3d face_centre(0, 0, -h.z());
  EdgeCheck out;
  for (int e = 0; e < 4; ++e) {
    for (double s : {0.3, 0.5, 0.7}) {
      const Eigen::Vector3d a = corners[e], b = corners[(e + 1) % 4];
      const Eigen::Vector3d p = a + s * (b - a);
      Eigen::Vector2d uv, uv_along, uv_in;
      EXPECT_TRUE(camera.project(T_cam_box * p, uv));
      EXPECT_TRUE(camera.project(T_cam_box * (p + 1e-3 * (b - a).normalized()), uv_along));
      EXPECT_TRUE(camera.project(T_cam_box * (p + 0.02 * (face_centre - p).normalized()), uv_in));
      const Eigen::Vector2d t = uv_along - uv;
      const bool vertical = std::abs(t.x()) < std::abs(t.y());
      const int i = vertical ? 0 : 1, j = 1 - i;  // scan along axis i in line (row/column) j
      const int line = static_cast<int>(std::lround(uv[j]));
      const double crossing = uv[i] + (line - uv[j]) * t[i] / t[j];
      const double in_crossing = uv[i] + (uv_in[j] - uv[j]) * t[i] / t[j];
      const bool face_after = uv_in[i] > in_crossing;  // the face lies towards larger u (or v)
      const int first = static_cast<int>(std::floor(crossing)) - 3, last = first + 7;
      double sum = 0.0;
      for (int k = first; k <= last; ++k) {
        const double c = vertical ? coverage(k, line) : coverage(line, k);
        sum += face_after ? 1.0 - c : c;
      }
      const double edge = first - 0.5 + sum;
      const double err = std::abs(edge - crossing);
      out.max_error_px = std::max(out.max_error_px, err);
      ++out.measured;
      EXPECT_LT(err, 0.25) << "edge " << e << " s " << s << " at (" << uv.transpose() << ") measured "
                           << edge << " model " << crossing;
    }
  }
  return out;
}

TEST(SyntheticCamera, BoxEdgesLieWhereTheModelProjectsThem) {
  // Four boxes facing the camera 1.5 m away at 0°, 50°, 85° and 105° off the optical axis: the
  // last one beyond 90°, behind the image plane, where only a >180° lens sees.
  const calib::GenericCamera camera = lens640();
  const Eigen::Isometry3d T_world_cam = someCameraPose();
  const Eigen::Vector3d h(0.25, 0.25, 0.1);
  const std::vector<Eigen::Isometry3d> T_cam_boxes = {
      facingPose(0.0, 0.0, 1.6), facingPose(50 * M_PI / 180, 0.5, 1.6),
      facingPose(85 * M_PI / 180, M_PI, 1.6), facingPose(105 * M_PI / 180, -0.6, 1.6)};
  auto scene = std::make_shared<cameras::SyntheticScene>();
  addPlainRoom(*scene);
  for (std::size_t i = 0; i < T_cam_boxes.size(); ++i)
    scene->addBox("box" + std::to_string(i), cameras::fixedPose(T_world_cam * T_cam_boxes[i]), h,
                  cameras::SurfaceStyle{kFaceRgb, false, 0});
  clock::SimClock clock;
  cameras::SyntheticCameraOptions options;
  options.supersampling = 4;
  const cameras::SyntheticCamera cam(camera, 640, 512, scene, cameras::fixedPose(T_world_cam), clock, options);
  const cameras::CameraFrame frame = cam.renderAt(0);
  ASSERT_EQ(frame.format, cameras::PixelFormat::kRgb8);
  ASSERT_EQ(frame.stride_bytes, 3 * 640);
  ASSERT_EQ(frame.pixels->size(), 640u * 512u * 3u);
  for (std::size_t i = 0; i < T_cam_boxes.size(); ++i) {
    SCOPED_TRACE("box " + std::to_string(i));
    const EdgeCheck check = checkBoxEdges(frame, camera, T_cam_boxes[i], h);
    EXPECT_EQ(check.measured, 12);
    std::printf("box %zu: max edge error %.3f px\n", i, check.max_error_px);
  }
  // The last box is seen beyond 90°: its face centre is behind the image plane.
  EXPECT_LT((T_cam_boxes[3] * Eigen::Vector3d(0, 0, -h.z())).z(), 0.0);
}

TEST(SyntheticCamera, RaysBeyondNinetyDegreesHitTheDefaultScene) {
  // The demo's head looking along +x of the robot: every valid ray, those beyond 90° included,
  // meets the room or an object; the rendered pixel is the scene's colour along that ray.
  const cameras::DefaultSceneLayout layout;
  auto scene = std::make_shared<cameras::SyntheticScene>(cameras::defaultScene(layout));
  Eigen::Isometry3d T_robot_cam = Eigen::Isometry3d::Identity();
  T_robot_cam.linear().col(0) = -Eigen::Vector3d::UnitY();  // optical x: the head's right
  T_robot_cam.linear().col(1) = -Eigen::Vector3d::UnitZ();  // optical y: down
  T_robot_cam.linear().col(2) = Eigen::Vector3d::UnitX();   // optical z: forward
  T_robot_cam.translation() = layout.head_position;
  const calib::GenericCamera camera = lens640();
  clock::SimClock clock;
  const cameras::SyntheticCamera cam(camera, 640, 512, scene, cameras::fixedPose(T_robot_cam), clock);
  const cameras::CameraFrame frame = cam.renderAt(0);
  const cameras::SceneView view = scene->view(0, T_robot_cam);
  int behind = 0, mismatched = 0, black = 0, valid = 0;
  std::array<int, 16> objects_seen{};
  for (int v = 0; v < 512; ++v) {
    for (int u = 0; u < 640; ++u) {
      Eigen::Vector3d d;
      if (!camera.unproject(Eigen::Vector2d(u, v), d)) continue;
      cameras::SceneHit hit;
      // The ray exactly as the camera stores it (unit, in float).
      const Eigen::Vector3d d_stored = d.normalized().cast<float>().cast<double>();
      ASSERT_TRUE(view.intersect(d_stored, &hit)) << u << ", " << v;
      ++objects_seen[static_cast<std::size_t>(hit.object)];
      const std::uint8_t* p = &(*frame.pixels)[(static_cast<std::size_t>(v) * 640 + u) * 3];
      const bool target = scene->objects()[static_cast<std::size_t>(hit.object)].kind ==
                          cameras::SceneObjectKind::kPlanarTarget;
      black += !target && p[0] + p[1] + p[2] == 0;  // tags are black, walls and boxes never
      if (d.z() < 0) ++behind;
      bool differs = false;
      for (int c = 0; c < 3; ++c) differs |= std::abs(p[c] - std::lround(hit.rgb[c])) > 1;
      mismatched += differs;
      ++valid;
    }
  }
  EXPECT_GT(behind, 5000);
  EXPECT_EQ(black, 0);
  // The same colour up to the last bit of the ray's rounding, which may put a handful of hits on
  // the other side of a 3.9 mm pattern cell's edge (4 of 300 000 pixels here).
  EXPECT_LE(mismatched, valid / 5000) << "of " << valid;
  for (const char* name : {"room", "box_1m", "box_2m", "box_left", "box_behind", "board", "marker"})
    EXPECT_GT(objects_seen[static_cast<std::size_t>(scene->find(name))], 20) << name;
  // box_behind is 95° off the optical axis: its near face's centre is behind the image plane.
  const auto& behind_box = scene->objects()[static_cast<std::size_t>(scene->find("box_behind"))];
  EXPECT_LT((T_robot_cam.inverse() * behind_box.T_world_object(0).translation()).z(), 0.0);
}

TEST(SyntheticCamera, RenderedAprilGridIsDetectedWithTheTrueBoardPose) {
  const auto lens = calib::synthetic::lens1280();
  const calib::AprilGrid grid = calib::synthetic::testGrid();
  const Eigen::Isometry3d T_world_cam = someCameraPose();
  const Eigen::Isometry3d T_cam_board = calib::synthetic::boardPoseAt(grid, 0.35, 0.8, 0.6, 0.25, -0.2, 0.1);
  // A textured room (moved to enclose this camera) behind the board.
  cameras::SyntheticScene board_scene;
  board_scene.addRoom("room", T_world_cam, Eigen::Vector3d(3, 3, 3), cameras::SurfaceStyle{{205, 185, 150}, true, 1},
                      cameras::SurfaceStyle{{160, 180, 205}, true, 2}, cameras::SurfaceStyle{{140, 110, 80}, true, 3},
                      cameras::SurfaceStyle{{235, 235, 228}, true, 4});
  board_scene.addAprilGrid("board", cameras::fixedPose(T_world_cam * T_cam_board), grid);
  clock::SimClock clock;
  cameras::SyntheticCameraOptions options;
  options.supersampling = 2;
  const cameras::SyntheticCamera cam(lens.camera, lens.width, lens.height,
                            std::make_shared<cameras::SyntheticScene>(std::move(board_scene)), cameras::fixedPose(T_world_cam),
                            clock, options);
  const cameras::CameraFrame frame = cam.renderAt(0);
  calib::GrayImage gray(frame.width, frame.height);
  for (std::size_t i = 0; i < gray.pixels.size(); ++i) {
    const std::uint8_t* p = &(*frame.pixels)[3 * i];
    gray.pixels[i] = static_cast<std::uint8_t>((p[0] + p[1] + p[2] + 1) / 3);
  }
  const calib::TargetObservation obs = calib::detectAprilGrid(gray, grid);
  ASSERT_GE(obs.corner_ids.size(), 120u) << "tags " << obs.tags_detected;
  double max_err = 0.0, sum2 = 0.0;
  std::vector<Eigen::Vector3d> p_board, d_cam;
  for (std::size_t i = 0; i < obs.corner_ids.size(); ++i) {
    Eigen::Vector2d truth;
    ASSERT_TRUE(lens.camera.project(T_cam_board * grid.cornerPosition(obs.corner_ids[i]), truth));
    const double e = (truth - obs.corners_px[i]).norm();
    max_err = std::max(max_err, e);
    sum2 += e * e;
    Eigen::Vector3d d;
    ASSERT_TRUE(lens.camera.unproject(obs.corners_px[i], d));
    p_board.push_back(grid.cornerPosition(obs.corner_ids[i]));
    d_cam.push_back(d.normalized());
  }
  const double rms = std::sqrt(sum2 / static_cast<double>(obs.corner_ids.size()));
  std::printf("aprilgrid: %zu corners, max %.3f px, rms %.3f px\n", obs.corner_ids.size(), max_err, rms);
  EXPECT_LT(max_err, 0.8);
  EXPECT_LT(rms, 0.3);
  const auto T_est = calib::planarPoseFromBearings(p_board, d_cam);
  ASSERT_TRUE(T_est);
  const double dt = (T_est->translation() - T_cam_board.translation()).norm();
  const double dr = Eigen::AngleAxisd(T_est->linear().transpose() * T_cam_board.linear()).angle();
  std::printf("board pose: %.2f mm, %.3f deg\n", dt * 1e3, dr * 180 / M_PI);
  EXPECT_LT(dt, 0.005);
  EXPECT_LT(dr, 0.5 * M_PI / 180);
}

TEST(SyntheticCamera, ImagesFollowThePoseAtCaptureTime) {
  // The camera yaws at 0.4 rad/s and slides sideways at 0.2 m/s: frames at 0 and 0.25 s show the
  // box where the model, at each frame's own pose, puts it.
  const calib::GenericCamera camera = lens640();
  const Eigen::Isometry3d T_world_cam0 = someCameraPose();
  const auto T_world_cam_at = [T_world_cam0](std::int64_t t_ns) {
    const double t = static_cast<double>(t_ns) * 1e-9;
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    motion.linear() = Eigen::AngleAxisd(0.4 * t, Eigen::Vector3d::UnitY()).toRotationMatrix();
    motion.translation() << 0.2 * t, 0, 0;
    return T_world_cam0 * motion;
  };
  const Eigen::Vector3d h(0.25, 0.25, 0.1);
  const Eigen::Isometry3d T_world_box = T_world_cam0 * facingPose(0.3, 0.0, 1.6);
  auto scene = std::make_shared<cameras::SyntheticScene>();
  addPlainRoom(*scene);
  scene->addBox("box", cameras::fixedPose(T_world_box), h, cameras::SurfaceStyle{kFaceRgb, false, 0});
  clock::SimClock clock;
  cameras::SyntheticCameraOptions options;
  options.supersampling = 4;
  const cameras::SyntheticCamera cam(camera, 640, 512, scene, T_world_cam_at, clock, options);
  Eigen::Vector2d centres[2];
  const std::int64_t times[2] = {0, 250'000'000};
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE("t_ns " + std::to_string(times[k]));
    const cameras::CameraFrame frame = cam.renderAt(times[k]);
    EXPECT_EQ(frame.capture_ns, times[k]);
    const Eigen::Isometry3d T_cam_box = T_world_cam_at(times[k]).inverse() * T_world_box;
    EXPECT_EQ(checkBoxEdges(frame, camera, T_cam_box, h).measured, 12);
    ASSERT_TRUE(camera.project(T_cam_box * Eigen::Vector3d(0, 0, -h.z()), centres[k]));
  }
  // The motion moved the box by tens of pixels: a renderer using the wrong pose fails above.
  EXPECT_GT((centres[1] - centres[0]).norm(), 20.0);
}

/// A small camera looking at the default scene while panning: frames at different times differ.
struct ThreadedRig {
  clock::SimClock clock{1'000'000};
  std::shared_ptr<cameras::SyntheticScene> scene = std::make_shared<cameras::SyntheticScene>(cameras::defaultScene());
  static Eigen::Isometry3d pose(std::int64_t t_ns) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.5 * static_cast<double>(t_ns) * 1e-9, Eigen::Vector3d::UnitZ()) *
                 (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished();
    T.translation() = cameras::DefaultSceneLayout{}.head_position;
    return T;
  }
  static calib::GenericCamera lens() {
    Eigen::VectorXd p(6);
    p << 78.75, 78.9, 159.5, 127.5, -0.18, 0.59;
    return *calib::GenericCamera::create("ds", p);
  }
};

TEST(SyntheticCamera, ThreadedSourceDeliversFramesAtClockTicks) {
  ThreadedRig rig;
  cameras::SyntheticCameraOptions options;
  options.name = "synthetic-left";
  options.fps = 50.0;  // ticks every 20 ms
  options.exposure_us = 4000;
  options.transfer_ns = 3'000'000;  // delivered 2 + 3 ms after the middle of the exposure
  cameras::SyntheticCamera cam(ThreadedRig::lens(), 320, 256, rig.scene, &ThreadedRig::pose, rig.clock, options);
  ASSERT_EQ(cam.periodNs(), 20'000'000);
  ASSERT_EQ(cam.deliveryDelayNs(), 5'000'000);
  EXPECT_EQ(cam.name(), "synthetic-left");
  std::string error;
  ASSERT_TRUE(cam.start(&error)) << error;
  // Nothing before the first tick (20 ms; the clock stands at 1 ms).
  EXPECT_FALSE(cam.nextFrame(std::chrono::milliseconds(30)));
  std::int64_t last_capture = -1;
  for (std::uint64_t i = 0; i < 5; ++i) {
    const std::int64_t tick = static_cast<std::int64_t>(i + 1) * 20'000'000;
    // At the middle of its exposure the frame is not read out yet; 5 ms later it is.
    rig.clock.set(tick);
    EXPECT_FALSE(cam.nextFrame(std::chrono::milliseconds(5))) << "frame " << i << " before its readout";
    rig.clock.set(tick + 5'000'000);
    const auto frame = cam.nextFrame(std::chrono::seconds(30));
    ASSERT_TRUE(frame) << "frame " << i;
    EXPECT_EQ(frame->sequence, i);
    EXPECT_EQ(frame->capture_ns, tick);
    EXPECT_GT(frame->capture_ns, last_capture);
    last_capture = frame->capture_ns;
    EXPECT_EQ(frame->exposure_us, 4000u);
    EXPECT_EQ(frame->width, 320);
    // Rendered at the pose of its capture time: identical to a direct render at that time.
    EXPECT_TRUE(*frame->pixels == *cam.renderAt(tick).pixels) << "frame " << i;
    if (i > 0) {
      EXPECT_FALSE(*frame->pixels == *cam.renderAt(tick - 20'000'000).pixels);
    }
  }
  // The clock jumps 2.5 periods past the next tick: the frame is exposed at the latest tick
  // whose frame is read out by now, the two ticks passed over are counted, the sequence has no gap.
  rig.clock.set(6 * 20'000'000 + 2 * 20'000'000 + 10'000'000);
  const auto late = cam.nextFrame(std::chrono::seconds(30));
  ASSERT_TRUE(late);
  EXPECT_EQ(late->capture_ns, 8 * 20'000'000);
  EXPECT_EQ(late->sequence, 5u);
  EXPECT_EQ(cam.skippedTicks(), 2u);
  const cameras::CameraStats stats = cam.stats();
  EXPECT_EQ(stats.frames, 6u);
  EXPECT_EQ(stats.lost, 0u);
  cam.stop();
  EXPECT_FALSE(cam.nextFrame(std::chrono::seconds(5)));
  cam.stop();  // idempotent
}

TEST(SyntheticCamera, FullQueueDropsTheOldestAsLost) {
  ThreadedRig rig;
  cameras::SyntheticCameraOptions options;
  options.fps = 50.0;
  options.queue_depth = 2;
  options.exposure_us = 0;  // delivered at the tick: the thread may look at the clock only then
  cameras::SyntheticCamera cam(ThreadedRig::lens(), 64, 48, rig.scene, &ThreadedRig::pose, rig.clock, options);
  ASSERT_TRUE(cam.start(nullptr));
  // Four ticks, each rendered before the next, nobody reading: the two oldest are lost.
  for (std::uint64_t i = 1; i <= 4; ++i) {
    rig.clock.set(static_cast<std::int64_t>(i) * 20'000'000);
    ASSERT_TRUE(test::eventually([&] { return cam.framesRendered() >= i; }, std::chrono::seconds(30)));
    ASSERT_EQ(cam.framesRendered(), i);
  }
  EXPECT_EQ(cam.stats().lost, 2u);
  for (std::uint64_t expected : {2u, 3u}) {
    const auto frame = cam.nextFrame(std::chrono::seconds(5));
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->sequence, expected);
  }
  EXPECT_EQ(cam.stats().frames, 2u);
  EXPECT_EQ(cam.skippedTicks(), 0u);
  cam.stop();
}

TEST(SyntheticCamera, StopAbandonsAFrameBeingRendered) {
  // stop() once the thread is rendering the rows of a large frame (1280×1024, 2×2 samples): it
  // returns with that frame unfinished — fewer rows rendered than the frame has (a few chunks of 8
  // here: 24–32 of 1024 measured) — and nothing delivered. Counted in rows, not timed.
  auto scene = std::make_shared<cameras::SyntheticScene>(cameras::defaultScene());
  const auto lens = calib::synthetic::lens1280();
  clock::SimClock clock(1);  // the first tick is then tick 1
  std::mutex m;
  std::condition_variable cv;
  bool rendering = false;
  const auto pose = [&](std::int64_t t_ns) {
    if (t_ns > 0) {
      std::lock_guard<std::mutex> lock(m);
      rendering = true;
      cv.notify_all();
    }
    return ThreadedRig::pose(0);
  };
  cameras::SyntheticCameraOptions options;
  options.supersampling = 2;
  cameras::SyntheticCamera cam(lens.camera, lens.width, lens.height, scene, pose, clock, options);
  ASSERT_TRUE(cam.start(nullptr));
  {
    // Each tick's delivery time in turn until the render thread is at work (the thread may
    // only look at the clock after the first of them).
    std::unique_lock<std::mutex> lock(m);
    for (std::int64_t k = 1; k <= 10 && !rendering; ++k) {
      clock.set(k * cam.periodNs() + cam.deliveryDelayNs());
      cv.wait_for(lock, std::chrono::seconds(3), [&] { return rendering; });
    }
    ASSERT_TRUE(rendering);
  }
  ASSERT_TRUE(test::eventually([&] { return cam.rowsRendered() > 0; }));  // its rows are under way
  cam.stop();
  const std::uint64_t rows = cam.rowsRendered();
  std::printf("rows rendered before the stop took: %llu of %d\n", static_cast<unsigned long long>(rows), lens.height);
  EXPECT_LT(rows, static_cast<std::uint64_t>(lens.height));
  EXPECT_EQ(cam.framesRendered(), 0u);
  EXPECT_FALSE(cam.nextFrame(std::chrono::milliseconds(0)));
  EXPECT_EQ(cam.stats().frames, 0u);
}

}  // namespace
}  // namespace telesphere::robot
