// SPDX-License-Identifier: MIT
/// @brief runOfflineReplay: the recording walked once, display frames rendered between its messages.
#include "xr/replay/offline_replay.h"

#include <algorithm>
#include <limits>
#include <map>

#include "calib/calibration_file.h"
#include "robot/link/link_pose.h"
#include "robot/record/recording_reader.h"
#include "shaders/egl_context.h"
#include "xr/frame_loop/eyes_png.h"
#include "xr/frame_loop/frame_clock.h"
#include "xr/frame_loop/operator_loop.h"
#include "xr/replay/recorded_view.h"

namespace telesphere::xr::replay {

std::optional<OfflineReplayStats> runOfflineReplay(const std::optional<calib::SystemCalibration>& given,
                                                   const OfflineReplayOptions& options,
                                                   const std::atomic<bool>& stop, std::string* error) {
  if (given && given->cameras.size() != 2) {
    *error = "the calibration needs two cameras";
    return std::nullopt;
  }
  if (!(options.display.rate_hz > 0.0 && options.display.rate_hz <= 1000.0)) {
    *error = "display rate must be in (0, 1000] Hz";
    return std::nullopt;
  }
  const std::string damaged_hint =
      " (for a damaged recording `telesphere-mcap check` says where, `telesphere-mcap recover` keeps its intact part)";
  const auto session = record::RecordingReader::open(options.recording, error);
  if (!session) {
    *error += damaged_hint;
    return std::nullopt;
  }
  const bool views_mode = !options.views.empty();
  if (views_mode && options.trajectory) {
    *error = "views from a live run bring their own head poses: not with a head trajectory";
    return std::nullopt;
  }
  if (views_mode && options.png_dir.empty()) {
    *error = "views from a live run are rendered into PNGs: give a folder for them";
    return std::nullopt;
  }
  const bool recorded_head = !options.trajectory && !views_mode;
  if (recorded_head) {
    const record::McapSummary& summary = session->summary();
    std::uint64_t head_targets = 0;
    for (const auto& [id, channel] : summary.channels) {
      const auto count = summary.channel_messages.find(id);
      if (channel.topic == "/xr/head_target" && count != summary.channel_messages.end()) head_targets += count->second;
    }
    if (head_targets == 0) {
      *error = options.recording + " holds no head targets (no operator app was connected while it was recorded): give a head trajectory";
      return std::nullopt;
    }
  }
  // The calibration to start with: the one given, or the one the recording began with.
  calib::SystemCalibration calibration;
  std::uint64_t first_generation = 0;
  std::string calibration_source;
  if (given) {
    calibration = *given;
    calibration_source = "given (overrides the recording's)";
  } else {
    const auto first = session->firstCalibration();
    if (!first) {
      *error = options.recording + " holds no calibration (recorded before calibrations were attached): give --calib FILE";
      return std::nullopt;
    }
    auto parsed = calib::parseCalibration(first->yaml, options.recording + " (calibration generation " +
                                                           std::to_string(first->generation) + ")");
    if (!parsed || parsed->cameras.size() != 2) {
      *error = parsed ? options.recording + ": its calibration does not have two cameras" : parsed.error().describe();
      return std::nullopt;
    }
    calibration = std::move(*parsed);
    first_generation = first->generation;
    calibration_source = "the recording's, generation " + std::to_string(first_generation);
  }
  auto context = gl::EglContext::createSurfaceless(error);
  if (!context || !context->makeCurrent()) {
    if (error->empty()) *error = "cannot make the EGL context current";
    return std::nullopt;
  }

  frame_loop::SimulatedFrameClock clock(std::numeric_limits<std::int64_t>::min());
  Eigen::Isometry3d T_vr_hmd_recorded = Eigen::Isometry3d::Identity();
  frame_loop::OffscreenOutput output(
      options.display,
      [&](double display_s) {
        return options.trajectory ? options.trajectory->sample(display_s, options.loop_trajectory) : T_vr_hmd_recorded;
      },
      &clock);
  if (!output.complete()) {
    *error = "cannot create " + std::to_string(options.display.eye_width) + "x" +
             std::to_string(options.display.eye_height) + " render targets";
    return std::nullopt;
  }
  RecordedView view(calibration, options.render, options.follow_recorded_settings, !given, first_generation,
                    options.depth_proxy, options.depth);
  frame_loop::OperatorLoop loop(view, output);
  OfflineReplayStats stats;

  // Display frames start at the first frame's log time, one period apart; a frame is drawn once
  // the first message logged after its start comes up (everything up to its start is in).
  std::optional<std::int64_t> first_start_ns, next_start_ns;
  bool taken_since_drawn = false, failed = false, ended = false;
  const auto draw = [&] {
    if (!loop.step(error)) return false;
    if (stats.first_frame_with_nominal == 0 && view.stats().nominal_from_robot)
      stats.first_frame_with_nominal = loop.stats().frames;
    if (!frame_loop::writeEveryNthEyesPng(options.png_dir, loop.stats().frames, options.png_every_frames, output.left(),
                              output.right(), error))
      return false;
    next_start_ns = output.nextStartNs();
    taken_since_drawn = false;
    if (options.progress) {
      const double total_s = double(static_cast<std::int64_t>(session->summary().end_ns) - *first_start_ns) * 1e-9;
      options.progress(double(*next_start_ns - *first_start_ns) * 1e-9,
                       options.duration_s > 0 ? std::min(options.duration_s, total_s) : total_s);
    }
    return true;
  };
  const auto due = [&] {
    ended = ended || stop ||
            (options.duration_s > 0 && double(*next_start_ns - *first_start_ns) >= options.duration_s * 1e9);
    return !ended;
  };
  record::RecordedSessionVisitor visitor;
  // Views mode: the live run's views by the camera frame they show, each drawn once that frame is in.
  std::multimap<std::uint64_t, const frame_loop::LoggedView*> views_by_sequence;
  for (const frame_loop::LoggedView& v : options.views) views_by_sequence.emplace(v.stereo_sequence, &v);
  const auto drawViewsOf = [&](std::uint64_t sequence) {
    const auto [begin, end] = views_by_sequence.equal_range(sequence);
    for (auto it = begin; it != end; ++it) {
      T_vr_hmd_recorded = it->second->T_vr_hmd;
      view.setLinkCues(it->second->link_state, it->second->image_saturation);
      if (!loop.step(error)) return false;
      if (!view.frame() || view.frame()->frame.sequence() != sequence) {
        *error = "view " + it->second->png + ": the recording's frame " + std::to_string(sequence) +
                 " did not decode (see above)";
        return false;
      }
      if (!frame_loop::writeEyesPng(options.png_dir + "/" + it->second->png, output.left(), output.right(), error)) return false;
      ++stats.views_rendered;
    }
    views_by_sequence.erase(begin, end);
    return true;
  };
  visitor.before = [&](std::int64_t log_time_ns) {
    if (views_mode) return !stop.load() && !views_by_sequence.empty();
    while (next_start_ns && *next_start_ns < log_time_ns) {
      if (!due()) return false;
      if (!draw()) {
        failed = true;
        return false;
      }
    }
    return !stop.load();
  };
  visitor.frame = [&](record::RecordedFrame&& frame) {
    if (!next_start_ns) {
      first_start_ns = next_start_ns = frame.log_time_ns;
      clock.sleepUntilNs(frame.log_time_ns);
    }
    const std::uint64_t sequence = frame.frame.sequence();
    const std::int64_t log_time_ns = frame.log_time_ns;
    view.takeFrame(std::move(frame));
    taken_since_drawn = true;
    if (views_mode && views_by_sequence.count(sequence) != 0) {
      clock.sleepUntilNs(log_time_ns);
      if (!drawViewsOf(sequence)) {
        failed = true;
        return false;
      }
    }
    return true;
  };
  visitor.calibration = [&](const record::RecordedCalibration& c) {
    if (given) return true;
    std::string why;
    if (!view.takeCalibration(c, &why)) ++stats.skipped;  // frames stamped with it keep the one before
    return true;
  };
  visitor.message = [&](record::RecordedTopic topic, const record::McapMessageView& m) {
    if (topic == record::RecordedTopic::kRobotState) {
      link::proto::RobotState state;
      if (state.ParseFromArray(m.data, static_cast<int>(m.size))) {
        view.takeState(state);
        taken_since_drawn = true;
      }
    } else if (topic == record::RecordedTopic::kXrTelemetry) {
      link::proto::XrTelemetry telemetry;
      if (telemetry.ParseFromArray(m.data, static_cast<int>(m.size))) view.takeXrTelemetry(telemetry);
    } else if (topic == record::RecordedTopic::kHeadTarget && recorded_head) {
      link::proto::HeadTarget target;
      if (target.ParseFromArray(m.data, static_cast<int>(m.size)) && target.valid()) {
        T_vr_hmd_recorded = link::fromLinkPose(target.t_vr_hmd());
        ++stats.head_targets;
        taken_since_drawn = true;
      }
    }
    return true;
  };
  if (!session->forEach(visitor, error)) {
    if (!failed) *error = options.recording + ": " + *error + damaged_hint;
    return std::nullopt;
  }
  if (failed) return std::nullopt;
  if (!first_start_ns) {
    *error = options.recording + " holds no complete stereo frame";
    return std::nullopt;
  }
  // What was logged after the last display frame's start.
  if (!views_mode && taken_since_drawn && due() && !draw()) return std::nullopt;
  for (const auto& [sequence, v] : views_by_sequence)
    if (stats.views_missing.size() < 20 &&
        (stats.views_missing.empty() || stats.views_missing.back() != sequence))
      stats.views_missing.push_back(sequence);

  stats.view = view.stats();
  stats.recorded_frames = session->frames();
  stats.undecodable = view.undecodable();
  stats.awaiting_key_frame = view.awaitingKeyFrame();
  stats.replaced_unshown = view.replacedUnshown();
  stats.skipped = session->skipped();
  stats.recording_s = double((views_mode ? clock.nowNs() : *next_start_ns) - *first_start_ns) * 1e-9;
  stats.calibration = calibration_source;
  if (!views_mode && !options.png_dir.empty() &&
      !frame_loop::writeEyesPng(options.png_dir + "/eyes_last.png", output.left(), output.right(), error))
    return std::nullopt;
  return stats;
}

}  // namespace telesphere::xr::replay
