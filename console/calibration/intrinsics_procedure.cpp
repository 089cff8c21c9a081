// SPDX-License-Identifier: MIT
/// @brief runIntrinsicsAuto (see intrinsics_procedure.h).
#include "console/calibration/intrinsics_procedure.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "calib/camera_resolution.h"
#include "robot/link/link_pose.h"

namespace telesphere::console::calibration {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string fmt(const char* f, double a = 0, double b = 0, double c = 0, double d = 0) {
  char buf[300];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

/// The targets a plan visits (each target's first pose; its fallbacks are not counted).
int firstChoices(const std::vector<PlannedView>& plan) {
  return int(std::count_if(plan.begin(), plan.end(), [](const PlannedView& v) { return !v.fallback; }));
}

/// The done rule's collection checks (views, polar bins of both cameras) on `collector`.
DoneCheck collectionCheck(const IntrinsicsCollector& collector, const IntrinsicsDoneRule& rule) {
  return checkCollection(int(collector.samples().size()), {&collector.coverage(0), &collector.coverage(1)},
                         ruleInEffect(rule, collector));
}

}  // namespace

calib::GenericCamera genericFisheye(const std::string& model, int width, int height) {
  // The focal length that puts a ray 100° off axis at the image's side, through the model's
  // default shape (stereographic for ds and eucm, equidistant for kb4).
  std::string error;
  double f = double(width) / (200.0 * M_PI / 180.0);
  if (auto unit = calib::GenericCamera::create(model, calib::defaultParams(model, 1.0, width, height), &error)) {
    Eigen::Vector2d px, centre;
    const double a = 100.0 * M_PI / 180.0;
    if (unit->project(Eigen::Vector3d(std::sin(a), 0, std::cos(a)), px) && unit->project(Eigen::Vector3d::UnitZ(), centre) &&
        px.x() > centre.x()) {
      f = 0.5 * width / (px.x() - centre.x());
    }
  }
  auto camera = calib::GenericCamera::create(model, calib::defaultParams(model, f, width, height), &error);
  if (!camera) camera = calib::GenericCamera::create("ds", calib::defaultParams("ds", f, width, height), &error);
  return *camera;
}

std::array<calib::GenericCamera, 2> startingModels(const IntrinsicsProcedureOptions& o, int width, int height) {
  std::array<calib::GenericCamera, 2> models{genericFisheye(o.model, width, height), genericFisheye(o.model, width, height)};
  if (o.initial && o.initial->cameras.size() == 2) {
    for (int c = 0; c < 2; ++c) {
      std::string error;
      if (auto scaled = calib::atResolution(o.initial->cameras[std::size_t(c)], width, height, &error)) {
        models[std::size_t(c)] = scaled->camera;
      }
    }
  }
  return models;
}

IntrinsicsOutcome runIntrinsicsAuto(CalibrationRobot& robot, const IntrinsicsProcedureOptions& o) {
  const auto t_start = Clock::now();
  IntrinsicsOutcome out;
  const auto log = [&](const std::string& line) {
    if (o.log) o.log(line);
  };
  const auto cancelled = [&] { return o.cancel != nullptr && o.cancel->load(); };
  std::string stage = "starting";
  const auto report = [&](int samples, const StereoSample* last_kept) {
    if (o.progress) o.progress(IntrinsicsProgress{stage, samples, out.poses_visited, out.poses_planned, last_kept});
  };
  // Once the run held the head: back to where it found it, then released (the supervisor placed
  // the board in view from there, and the next run starts from it), cancelled runs too.
  std::optional<Eigen::Isometry3d> T_robot_head_start;
  const auto giveHeadBack = [&] {
    std::string error;
    if (T_robot_head_start) {
      if (robot.returnHeadTo(*T_robot_head_start, o.settle, &error)) {
        out.head_returned = true;
        log("the head is back at its start pose");
      } else {
        out.head_return_error = error;
        log("the head could not be taken back to its start pose: " + error);
      }
    }
    robot.release(&error);
  };
  const auto fail = [&](const std::string& why) {
    out.error = why;
    giveHeadBack();
    out.total_s = secondsSince(t_start);
    log("failed: " + why);
    return out;
  };
  out.rule_text = o.rule.describe(o.coverage.polar_bin_deg);
  log("done rule: " + out.rule_text);

  // 1. Hold where the head is and find the board.
  std::string error;
  const auto T_robot_head0 = robot.headPose(std::chrono::seconds(5));
  if (!T_robot_head0) return fail("no robot state with the head pose within 5 s (is telesphere-robot running?)");
  if (!robot.holdHeadAt(*T_robot_head0, &error)) return fail("cannot hold the head: " + error);
  T_robot_head_start = *T_robot_head0;
  if (!robot.waitSettled(*T_robot_head0, o.settle, o.cancel, &error)) return fail(error);
  // The cameras may still be starting: a few tries for the first still.
  std::optional<link::proto::CalibrationStill> first_still;
  for (int attempt = 0; attempt < 5 && !first_still && !cancelled(); ++attempt) {
    first_still = robot.takeStill(&error);
    if (!first_still) log("no still yet (" + error + ")");
  }
  if (!first_still) return fail("no still: " + error);
  ++out.stills;
  const StereoSample first = detectStereoSample(*first_still, o.grid, o.detection);
  const int width = first.width, height = first.height;
  if (width <= 0) return fail("the robot's still holds no image");
  std::array<calib::GenericCamera, 2> models = startingModels(o, width, height);
  if (int(first.views[0].corner_ids.size()) < o.gates.min_corners) {
    return fail(fmt("the Aprilgrid is not in view of the left camera at the start (%.0f corners, %.0f needed): "
                    "place it about 1 m in front of the head, wholly visible",
                    double(first.views[0].corner_ids.size()), o.gates.min_corners));
  }
  const auto p_cam_board = boardCentreInCamera(first.views[0], o.grid, models[0]);
  if (!p_cam_board) return fail("cannot tell where the board is from the first view");
  const Eigen::Isometry3d T_robot_cam0 = link::fromLinkPose(first_still->left().t_robot_cam());
  const Eigen::Isometry3d T_head_cam = T_robot_head0->inverse() * T_robot_cam0;
  const Eigen::Vector3d p_robot_board = T_robot_cam0 * *p_cam_board;
  log(fmt("board found %.2f m from the left camera; stills %.0f×%.0f", p_cam_board->norm(), width, height));

  IntrinsicsCollector collector(models, width, height, o.gates, o.coverage);
  double board_distance_m = p_cam_board->norm();
  collector.setTagAngleDeg(tagAngleDeg(o.grid, board_distance_m));
  std::optional<Clock::time_point> t_first_sample;
  std::ofstream stills_csv;
  if (!o.stills_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.stills_dir, ec);
    stills_csv.open(o.stills_dir + "/stills.csv");
    if (!stills_csv) return fail("cannot write " + o.stills_dir + "/stills.csv");
    stills_csv << "still,capture_ns,target_u_px,target_v_px,roll_deg,corners_left,corners_right,verdict\n";
  }
  // Writes the still's images and its row (when --save-stills is on).
  const auto keepStill = [&](const link::proto::CalibrationStill& still, const StereoSample& sample,
                             const PlannedView& view, const std::string& verdict) {
    if (!stills_csv.is_open()) return;
    char name[64];
    std::snprintf(name, sizeof name, "%s/still-%03d", o.stills_dir.c_str(), out.stills);
    calib::writeGrayImage(grayImageOf(still.left()), std::string(name) + "-left.png");
    calib::writeGrayImage(grayImageOf(still.right()), std::string(name) + "-right.png");
    std::string v = verdict;
    for (char& ch : v)
      if (ch == ',' || ch == '"') ch = ' ';
    stills_csv << out.stills << ',' << still.capture_ns() << ',' << view.target_px.x() << ',' << view.target_px.y() << ','
               << view.roll_deg << ',' << sample.views[0].corner_ids.size() << ',' << sample.views[1].corner_ids.size()
               << ',' << v << '\n'
               << std::flush;
  };

  // 2./3. Visit planned poses.
  // Poses that gave nothing for a reason that may pass (not settled, no still, still moving on
  // a loaded machine): visited once more at the end while the rule is unmet.
  std::vector<PlannedView> missed;
  // Whether a pose is refused depends on where the arm stands (the robot checks the path its
  // controller takes from there; a path can stall where the wrist lines up). The plan was made
  // from the start pose, so a refused pose is asked for once more from there.
  bool head_at_start = true;
  const auto holdView = [&](const PlannedView& view) -> bool {
    if (robot.holdHeadAt(view.T_robot_head, &error)) {
      head_at_start = false;
      return true;
    }
    log(fmt("pose for pixel (%.0f, %.0f), roll %.0f°, refused: ", view.target_px.x(), view.target_px.y(), view.roll_deg) +
        error);
    if (head_at_start) return false;
    std::string why;
    if (!robot.holdHeadAt(*T_robot_head0, &why) || !robot.waitSettled(*T_robot_head0, o.settle, o.cancel, &why)) {
      log("could not take the head back to its start pose: " + why);
      return false;
    }
    head_at_start = true;
    if (!robot.holdHeadAt(view.T_robot_head, &error)) {
      log("refused from the start pose too: " + error);
      return false;
    }
    ++out.poses_held_from_start;
    log("held when approached from the start pose");
    head_at_start = false;
    return true;
  };
  // A view for another visit (missed): visited for its own sake, not as a fallback.
  const auto miss = [&](const PlannedView& view) {
    missed.push_back(view);
    missed.back().fallback = false;
  };
  // Counts a target (a first choice and its fallbacks) once: visited, and refused when the arm
  // took none of its poses.
  const auto visit = [&](const std::vector<PlannedView>& plan, bool stop_when_collected) -> bool {
    bool target_open = false;     // no pose of this target held yet: its fallbacks are still wanted
    bool target_refused = false;  // and the arm refused one of them
    const auto closeTarget = [&] {
      if (target_open && target_refused) ++out.poses_refused;
      target_open = target_refused = false;
    };
    for (const PlannedView& view : plan) {
      if (!view.fallback) {
        closeTarget();
        target_open = true;
      } else if (!target_open) {
        continue;
      }
      if (cancelled()) return false;
      if (int(collector.samples().size()) >= o.max_views) break;
      if (stop_when_collected && collectionCheck(collector, o.rule).done()) break;
      if (!view.fallback) ++out.poses_visited;
      if (!holdView(view)) {
        if (cancelled()) return false;
        target_refused = true;
        continue;
      }
      if (cancelled()) return false;
      target_open = target_refused = false;
      if (view.fallback) {
        ++out.fallback_poses_held;
        log(fmt("another pose for pixel (%.0f, %.0f) is held: roll %.0f°", view.target_px.x(), view.target_px.y(),
                view.roll_deg));
      }
      if (!robot.waitSettled(view.T_robot_head, o.settle, o.cancel, &error)) {
        if (cancelled()) return false;
        ++out.poses_unsettled;
        log("pose skipped: " + error);
        miss(view);
        continue;
      }
      std::optional<StereoSample> previous;
      bool settled_outcome = false;  // kept, or a verdict another visit would not change
      for (int s = 0; s < o.max_stills_per_pose; ++s) {
        auto still = robot.takeStill(&error);
        if (!still) {
          log("no still: " + error);
          break;
        }
        ++out.stills;
        StereoSample sample = detectStereoSample(*still, o.grid, o.detection);
        if (!t_first_sample) t_first_sample = Clock::now();
        if (!previous) {
          keepStill(*still, sample, view, "first at this pose");
          previous = std::move(sample);
          continue;
        }
        const SampleVerdict verdict = collector.offer(sample, &*previous);
        keepStill(*still, sample, view, verdict.keep ? "kept" : verdict.reason);
        if (verdict.keep) {
          log(fmt("sample %.0f kept at pixel (%.0f, %.0f): ", double(collector.samples().size()), view.target_px.x(),
                  view.target_px.y()) +
              collector.coverage(0).describe());
          report(int(collector.samples().size()), &collector.samples().back());
          settled_outcome = true;
          break;
        }
        ++out.samples_rejected;
        log("sample not kept: " + verdict.reason);
        if (!verdict.moving) {
          settled_outcome = true;
          break;  // another still at this pose would not change the verdict
        }
        previous = std::move(sample);
      }
      if (!settled_outcome) miss(view);
      report(int(collector.samples().size()), nullptr);
    }
    closeTarget();
    return true;
  };

  ViewPlanOptions plan_options;
  // The head poses of one ring of targets through `camera`, counted as planned and logged.
  const auto planRing = [&](const char* name, std::vector<Eigen::Vector2d> targets, const calib::GenericCamera& camera) {
    plan_options.targets = std::move(targets);
    auto ring = planIntrinsicViews(*T_robot_head0, T_head_cam, p_robot_board, camera, width, height, plan_options);
    out.poses_planned += firstChoices(ring);
    log(std::string(name) + fmt(": %.0f poses planned", double(firstChoices(ring))));
    stage = name;
    return ring;
  };
  auto plan = planRing("inner views", ViewPlanOptions::innerTargets(), models[0]);
  if (!visit(plan, false)) return fail("cancelled");

  // A quick solve refines the models the rim is planned and the coverage is measured through.
  {
    calib::IntrinsicOptions quick;
    quick.covariance = false;
    quick.max_iterations = 50;
    if (auto solved = calib::calibrateIntrinsics(o.grid, collector.cameraViews(o.model), quick)) {
      for (int c = 0; c < 2; ++c) models[std::size_t(c)] = solved->cameras[std::size_t(c)].calibration.camera;
      collector.setModels(models);
      if (const auto p = boardCentreInCamera(first.views[0], o.grid, models[0])) {  // through the refined model
        board_distance_m = p->norm();
        collector.setTagAngleDeg(tagAngleDeg(o.grid, board_distance_m));
      }
      log(fmt("quick solve on %.0f views: RMS %.3f / %.3f px", double(solved->cameras[0].views_used),
              solved->cameras[0].rms_px, solved->cameras[1].rms_px));
    } else {
      log("quick solve failed (" + solved.failure().message + "); planning the rim with the first models");
    }
  }
  {
    // The rim bins where the board's tags are too small to read are not asked for; say which
    // (through the quick solve's models: the start's may squeeze the rim less than the lens does).
    const IntrinsicsDoneRule rule = ruleInEffect(o.rule, collector);
    for (int c = 0; c < 2; ++c) {
      const calib::ViewCoverage& cov = collector.coverage(c);
      for (int b : unreadablePolarBins(cov, rule))
        log(std::string(c == 0 ? "cam_l" : "cam_r") +
            fmt(": the %.0f–%.0f° ring is not required: a tag %.2f m away spans %.1f px radially there, ",
                b * cov.polarBinDeg(), (b + 1) * cov.polarBinDeg(), board_distance_m,
                cov.radialPxPerDeg(b) * rule.tag_angle_deg) +
            fmt("%.0f needed (bring the board closer, or use a higher resolution, to cover it)",
                rule.tag_cells * rule.min_px_per_tag_cell));
    }
  }
  plan = planRing("rim views", ViewPlanOptions::outerTargets(), models[0]);
  if (!visit(plan, true)) return fail("cancelled");
  // While the rule is unmet: the poses that gave nothing once more, then a fill ring.
  if (!collectionCheck(collector, o.rule).done()) {
    std::vector<PlannedView> retry;
    retry.swap(missed);
    log(fmt("the rule is not met yet: %.0f poses again", double(retry.size())));
    stage = "retrying";
    if (!visit(retry, true)) return fail("cancelled");
    plan_options.rolls_deg = {15.0, -15.0, 45.0, -45.0};
    plan = planRing("fill views", ViewPlanOptions::fillTargets(), models[0]);
    if (!visit(plan, true)) return fail("cancelled");
  }

  // 4. The stereo solve, with the head still held: when the views meet the rule but the solve
  // misses a σ or RMS bound (one Release run here: σ(fx) 0.982 px, 0.97 allowed, from 20 samples),
  // one ring of further views (the fill targets at other rolls) and the solve again.
  log(fmt("collected %.0f samples (%.0f joint views); ", double(collector.samples().size()),
          double(collector.jointViews())) +
      "cam_l " + collector.coverage(0).describe() + "; cam_r " + collector.coverage(1).describe());
  stage = "solving";
  report(int(collector.samples().size()), nullptr);
  solveCollected(std::move(collector), o, out);
  if (out.result && out.collection.done() && !out.solve.done() && out.collector &&
      int(out.collector->samples().size()) < o.max_views) {
    collector = std::move(*out.collector);
    log("the solve misses the rule (" + out.solve.describe() + "): more views");
    plan_options.rolls_deg = {30.0, -30.0, 60.0, -60.0};
    plan = planRing("more views", ViewPlanOptions::fillTargets(), out.result->cameras[0].calibration.camera);
    if (!visit(plan, false)) {
      out.collector = std::move(collector);  // the first solve's samples stay with its result
      return fail("cancelled");
    }
    log(fmt("collected %.0f samples; solving again", double(collector.samples().size())));
    stage = "solving";
    report(int(collector.samples().size()), nullptr);
    solveCollected(std::move(collector), o, out);
  }
  giveHeadBack();
  out.first_sample_to_result_s = out.result && t_first_sample ? secondsSince(*t_first_sample) : 0.0;
  out.total_s = secondsSince(t_start);
  return out;
}

double tagAngleDeg(const calib::AprilGrid& grid, double distance_m) {
  return 2.0 * std::atan(0.5 * grid.tag_size / distance_m) * 180.0 / M_PI;
}

IntrinsicsDoneRule ruleInEffect(const IntrinsicsDoneRule& rule, const IntrinsicsCollector& collector) {
  IntrinsicsDoneRule r = rule;
  if (r.tag_angle_deg <= 0) r.tag_angle_deg = collector.tagAngleDeg();
  return r;
}

void solveCollected(IntrinsicsCollector collector, const IntrinsicsProcedureOptions& o, IntrinsicsOutcome& out) {
  const auto log = [&](const std::string& line) {
    if (o.log) o.log(line);
  };
  out.result.reset();
  out.calibration.reset();
  out.collection = collectionCheck(collector, o.rule);
  out.solve = DoneCheck{};
  calib::IntrinsicOptions solve_options;
  solve_options.progress = [&](const std::string& line) { log("solve: " + line); };
  auto solved = calib::calibrateIntrinsics(o.grid, collector.cameraViews(o.model), solve_options);
  if (!solved) {
    out.collector = std::move(collector);
    out.done = false;
    out.error = (out.collection.done() ? std::string() : "the done rule is not met: " + out.collection.describe() + "; ") +
                "the solve failed: " + solved.failure().message;
    log("failed: " + out.error);
    return;
  }
  out.result = *solved;
  collector.setModels({solved->cameras[0].calibration.camera, solved->cameras[1].calibration.camera});
  out.collection = collectionCheck(collector, o.rule);
  out.solve = checkSolve(*solved, o.rule);
  calib::SystemCalibration calibration = solved->toSystemCalibration();
  if (o.initial) {
    calibration.T_flange_cam_l = o.initial->T_flange_cam_l;
    calibration.T_robot_mount = o.initial->T_robot_mount;
    calibration.T_wrist_marker = o.initial->T_wrist_marker;
  }
  out.calibration = calibration;
  out.collector = std::move(collector);
  out.done = out.collection.done() && out.solve.done();
  out.error.clear();
  if (!out.done) {
    out.error = "the done rule is not met: " + (out.collection.done() ? std::string() : out.collection.describe()) +
                (out.collection.done() || out.solve.done() ? "" : "; ") + (out.solve.done() ? "" : out.solve.describe());
  }
  log(out.done ? "done" : out.error);
}

}  // namespace telesphere::console::calibration
