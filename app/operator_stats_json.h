// SPDX-License-Identifier: MIT
/// @brief The operator view's figures as the JSON keys every `telesphere-xr` mode writes to its
///        stats.json (the keys `telesphere-bench xr --json` also uses).
#pragma once

#include <nlohmann/json.hpp>

#include "xr/frame_loop/operator_view.h"

namespace telesphere::app {

inline nlohmann::json operatorStatsJson(const xr::frame_loop::OperatorViewStats& s) {
  return {{"render_ms", s.render_ms_p50},
          {"render_ms_p99", s.render_ms_p99},
          {"image_age_p50_ms", s.image_age_p50_ms},
          {"image_age_p99_ms", s.image_age_p99_ms},
          {"pose_to_display_ms", s.pose_to_display_ms_p50},
          {"stereo_frames_shown", s.stereo_frames_shown},
          {"upload_ms_render_thread_p50", s.upload_ms_render_thread_p50},
          {"upload_ms_render_thread_p99", s.upload_ms_render_thread_p99},
          {"decode_ms_p50", s.decode_ms_p50},
          {"images_in_upload_slots", s.images_in_upload_slots},
          {"images_in_own_memory", s.images_in_own_memory},
          {"head_targets_sent", s.head_targets_sent},
          {"nominal_from_robot", s.nominal_from_robot},
          {"settings_changes", s.settings_changes},
          {"calibration_generation", s.calibration_generation},
          {"calibration_changes", s.calibration_changes},
          {"video_link", s.video_link},
          {"media_datagrams", s.media_datagrams},
          {"media_frames_whole", s.media_frames_whole},
          {"media_frames_concealed", s.media_frames_concealed},
          {"media_frames_lost", s.media_frames_lost},
          {"media_bands_lost", s.media_bands_lost},
          {"media_chunks_fec", s.media_chunks_fec},
          {"media_chunks_requested", s.media_chunks_requested},
          {"media_chunks_repaired", s.media_chunks_repaired},
          {"media_frames_superseded", s.media_frames_superseded},
          {"frames_concealed", s.frames_concealed},
          {"rows_concealed", s.rows_concealed},
          {"rows_grey", s.rows_grey},
          {"video_codec", s.video_codec},
          {"key_frames_requested", s.key_frames_requested},
          {"frames_awaiting_key_frame", s.frames_awaiting_key_frame},
          {"frames_tinted", s.frames_tinted},
          {"frames_stale", s.frames_stale},
          {"frames_stream_below_nominal", s.frames_stream_below_nominal},
          {"frames_robot_behind", s.frames_robot_behind},
          {"depth_proxy", s.depth_proxy},
          {"depth_estimates", s.depth_estimates},
          {"depth_pairs_skipped", s.depth_pairs_skipped},
          {"depth_sweep_ms", s.depth_sweep_ms},
          {"depth_radius_left_m", s.depth_radius_left_m},
          {"depth_matched_fraction", s.depth_matched_fraction},
          {"depth_motion_views_left", s.depth_motion_views_left},
          {"depth_motion_baseline_left_m", s.depth_motion_baseline_left_m},
          {"depth_tiles_decided_by_motion_left", s.depth_tiles_decided_by_motion_left},
          {"depth_sweep_on_gpu", s.depth_sweep_on_gpu},
          {"depth_gpu_unavailable", s.depth_gpu_unavailable},
          {"depth_images_with_own_depth", s.depth_images_with_own_depth},
          {"depth_images_held", s.depth_images_held},
          {"depth_hold_timeouts", s.depth_hold_timeouts},
          {"depth_hold_ms_p50", s.depth_hold_ms_p50},
          {"depth_hold_ms_p99", s.depth_hold_ms_p99}};
}

}  // namespace telesphere::app
