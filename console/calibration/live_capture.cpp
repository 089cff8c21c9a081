// SPDX-License-Identifier: MIT
/// @brief LiveCapture (see live_capture.h).
#include "console/calibration/live_capture.h"

namespace telesphere::console::calibration {

LiveCapture::LiveCapture(CalibrationRobot& robot, IntrinsicsProcedureOptions options, int view_width)
    : robot_(robot), options_(std::move(options)), view_width_(view_width) {}

std::optional<LiveStill> LiveCapture::step(std::string* error) {
  const auto still = robot_.takeStill(error);
  if (!still) return std::nullopt;
  ++stills_;
  LiveStill live;
  // One grey copy of each image: detected, and reduced to the live view's width, from which the
  // sample list's thumbnail is reduced again.
  live.sample = detectStereoSample(*still, options_.grid, options_.detection, view_width_);
  live.view = live.sample.thumbnails;
  for (calib::GrayImage& thumbnail : live.sample.thumbnails) thumbnail = thumbnailOf(thumbnail);
  if (live.sample.width <= 0) {
    *error = "the robot's still holds no image";
    return std::nullopt;
  }
  if (!collector_) {
    collector_.emplace(startingModels(options_, live.sample.width, live.sample.height), live.sample.width,
                       live.sample.height, options_.gates, options_.coverage);
  } else if (collector_->width() != live.sample.width || collector_->height() != live.sample.height) {
    *error = "the stills are " + std::to_string(live.sample.width) + "×" + std::to_string(live.sample.height) +
             " but the samples kept so far are " + std::to_string(collector_->width()) + "×" +
             std::to_string(collector_->height()) + " (the cameras changed): start a new calibration";
    return std::nullopt;
  }
  live.verdict = collector_->judge(live.sample, previous_ ? &*previous_ : nullptr);
  if (live.verdict.keep && (auto_capture_ || capture_requested_.exchange(false))) {
    collector_->add(live.sample);
    live.kept = true;
    if (collector_->tagAngleDeg() <= 0) {  // the board's distance from the first kept sample that gives it
      const auto models = startingModels(options_, live.sample.width, live.sample.height);
      if (const auto p_cam_board = boardCentreInCamera(live.sample.views[0], options_.grid, models[0]))
        collector_->setTagAngleDeg(tagAngleDeg(options_.grid, p_cam_board->norm()));
    }
  }
  live.capture_pending = capture_requested_;
  live.samples = int(collector_->samples().size());
  previous_ = live.sample;
  return live;
}

}  // namespace telesphere::console::calibration
