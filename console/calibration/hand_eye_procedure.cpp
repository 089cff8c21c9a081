// SPDX-License-Identifier: MIT
/// @brief runHandEyeAuto (see hand_eye_procedure.h).
#include "console/calibration/hand_eye_procedure.h"

#include <cmath>
#include <cstdio>

#include "calib/camera_resolution.h"

namespace telesphere::console::calibration {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

std::optional<calib::SystemCalibration> camerasAt(const calib::SystemCalibration& cameras, int width, int height,
                                                  std::string* error) {
  calib::SystemCalibration out = cameras;
  for (calib::CameraCalibration& camera : out.cameras) {
    if (camera.width == width && camera.height == height) continue;
    auto scaled = calib::atResolution(camera, width, height, error);
    if (!scaled) return std::nullopt;
    camera = *scaled;
  }
  return out;
}

void takeSolve(HandEyeOutcome& out, const calib::SystemCalibration& cameras, bool ok, const std::string& error) {
  const HandEyeCollector& c = *out.collector;
  out.check = c.check();
  out.done = ok && out.check.done();
  out.calibration.reset();
  if (ok) out.calibration = withHandEye(cameras, *c.result());
  out.error = ok ? (out.done ? "" : out.check.describe()) : error;
}

HandEyeOutcome runHandEyeAuto(CalibrationRobot& robot, const HandEyeProcedureOptions& options) {
  const auto log = [&](const std::string& line) {
    if (options.log) options.log(line);
  };
  const auto t_start = Clock::now();
  HandEyeOutcome out;
  out.rule_text = options.collector.rule.describe();
  std::optional<Eigen::Isometry3d> T_robot_head_start;  // set once the pattern or hold started
  const auto finish = [&](std::string error) {
    std::string ignored;
    if (T_robot_head_start) {
      if (robot.returnHeadTo(*T_robot_head_start, options.settle, &ignored)) {
        out.head_returned = true;
        log("the head is back at its start pose");
      } else {
        out.head_return_error = ignored;
        log("the head could not be taken back to its start pose: " + ignored);
      }
    }
    robot.release(&ignored);
    out.error = std::move(error);
    out.total_s = secondsSince(t_start);
    if (!out.error.empty()) log("not done: " + out.error);
    return out;
  };
  if (options.cameras.cameras.size() != 2 || !options.cameras.T_cam_l_cam_r)
    return finish("the hand-eye calibration needs both cameras' intrinsics and T_cam_l_cam_r (run the intrinsics first)");

  std::string error;
  const auto T_head = robot.headPose(std::chrono::seconds(5));
  if (!T_head) return finish("no robot state within 5 s");
  if (options.pattern_amplitude_deg > 0) {
    if (!robot.runHeadPattern(options.pattern_amplitude_deg, &error)) return finish("head pattern refused: " + error);
    T_robot_head_start = *T_head;
    log("the head moves along the calibration pattern (±" + std::to_string(int(options.pattern_amplitude_deg)) +
        "° yaw); move the manipulator with the marker in view");
  } else {
    if (!robot.holdHeadAt(*T_head, &error)) return finish("head hold refused: " + error);
    T_robot_head_start = *T_head;
    log("the head holds still (no pattern): the head's rotations will not separate the unknowns");
  }

  std::optional<Clock::time_point> t_first_sample;
  while (true) {
    if (options.cancel != nullptr && options.cancel->load()) return finish("cancelled");
    if (Clock::now() - t_start > options.time_limit)
      return finish("time limit of " + std::to_string(options.time_limit.count()) + " s reached: " + out.check.describe());
    if (out.stills >= options.max_stills) return finish("took " + std::to_string(out.stills) + " stills: " + out.check.describe());
    if (out.collector && int(out.collector->samples().size()) >= options.max_samples)
      return finish(std::to_string(options.max_samples) + " samples kept and the done rule unmet: " + out.check.describe());

    auto still = robot.takeStill(&error);
    if (!still) return finish("no still: " + error);
    ++out.stills;
    HandEyeProgress progress;
    progress.stills = out.stills;
    std::string reason;
    auto sample = handEyeSampleOf(*still, options.marker, &reason);
    if (sample && !out.collector) {
      auto scaled = camerasAt(options.cameras, sample->width, sample->height, &error);
      if (!scaled) return finish(error);
      out.collector.emplace(*scaled, options.marker, options.collector);
    }
    if (!sample) {
      ++out.refused;
    } else if (!out.collector->offer(*sample, &reason)) {
      ++out.too_close;
    } else {
      progress.kept = true;
      if (!t_first_sample) t_first_sample = Clock::now();
    }
    progress.verdict = progress.kept ? "kept" : reason;
    if (!progress.kept) log("still " + std::to_string(out.stills) + ": " + reason);
    if (out.collector) {
      HandEyeCollector& c = *out.collector;
      const int n = int(c.samples().size());
      if (progress.kept && n >= options.collector.auto_solve_from) {
        HandEyeSolveStep step;
        step.samples = n;
        step.ok = c.solve(&step.error);
        if (step.ok && options.remove_outliers) {
          if (const int removed = c.removeOutliers(); removed > 0) {
            out.outliers_removed += removed;
            log("removed " + std::to_string(removed) + " outlier sample(s)");
            step.samples = int(c.samples().size());
            step.ok = c.solve(&step.error);
          }
        }
        step.elapsed_s = secondsSince(*t_first_sample);
        if (step.ok) {
          const calib::HandEyeResult& r = *c.result();
          step.rms_px = std::max(r.rms_px_l, r.rms_px_r);
          step.flange_cam_sigma_t_mm = r.stddev[0].translation_m.norm() * 1e3;
          step.flange_cam_sigma_r_deg = r.stddev[0].rotation_deg.norm();
          step.result = r;
        }
        takeSolve(out, options.cameras, step.ok, step.error);
        char buf[300];
        if (step.ok) {
          std::snprintf(buf, sizeof buf, "%d samples: RMS %.2f px, T_flange_cam_l σ %.2f mm / %.3f°; %s", step.samples,
                        step.rms_px, step.flange_cam_sigma_t_mm, step.flange_cam_sigma_r_deg, out.check.describe().c_str());
        } else {
          std::snprintf(buf, sizeof buf, "%d samples: no solution: %s", step.samples, step.error.c_str());
        }
        log(buf);
        out.history.push_back(std::move(step));
        if (out.done) out.first_sample_to_result_s = secondsSince(*t_first_sample);
      } else if (progress.kept) {
        out.check = c.check();
      }
      progress.collector = &c;
    }
    progress.check = out.check;
    if (options.progress) options.progress(progress);
    if (out.done) return finish("");
  }
}

}  // namespace telesphere::console::calibration
