// SPDX-License-Identifier: MIT
/// @brief IntrinsicsCollector (see intrinsics_collector.h).
#include "console/calibration/intrinsics_collector.h"

namespace telesphere::console::calibration {

IntrinsicsCollector::IntrinsicsCollector(const std::array<calib::GenericCamera, 2>& models, int width, int height,
                                         const calib::SampleGateOptions& gates, const calib::CoverageOptions& coverage)
    : models_(models), width_(width), height_(height), gates_(gates), coverage_options_(coverage) {
  rebuildCoverage();
}

SampleVerdict IntrinsicsCollector::judge(const StereoSample& sample, const StereoSample* previous) const {
  SampleVerdict verdict;
  bool any_keep = false;
  for (int c = 0; c < 2; ++c) {
    std::vector<calib::TargetObservation> kept;
    kept.reserve(samples_.size());
    for (const StereoSample& s : samples_) kept.push_back(s.views[std::size_t(c)]);
    const calib::GateResult g =
        calib::judgeView(sample.views[std::size_t(c)], previous ? &previous->views[std::size_t(c)] : nullptr, kept, gates_);
    verdict.reason += std::string(verdict.reason.empty() ? "" : "; ") + (c == 0 ? "cam_l: " : "cam_r: ") + g.reason;
    if (g.verdict == calib::GateVerdict::kKeep) any_keep = true;
    if (g.verdict == calib::GateVerdict::kMoving || g.verdict == calib::GateVerdict::kNoPreviousView)
      verdict.moving = true;
  }
  verdict.keep = any_keep && !verdict.moving;
  return verdict;
}

SampleVerdict IntrinsicsCollector::offer(const StereoSample& sample, const StereoSample* previous) {
  SampleVerdict verdict = judge(sample, previous);
  if (verdict.keep) add(sample);
  return verdict;
}

void IntrinsicsCollector::add(const StereoSample& sample) {
  samples_.push_back(sample);
  for (int c = 0; c < 2; ++c) coverage_[std::size_t(c)].add(sample.views[std::size_t(c)]);
}

void IntrinsicsCollector::remove(std::size_t index) {
  if (index >= samples_.size()) return;
  samples_.erase(samples_.begin() + std::ptrdiff_t(index));
  rebuildCoverage();
}

void IntrinsicsCollector::setModels(const std::array<calib::GenericCamera, 2>& models) {
  models_ = models;
  rebuildCoverage();
}

void IntrinsicsCollector::rebuildCoverage() {
  coverage_.clear();
  for (int c = 0; c < 2; ++c) {
    coverage_.emplace_back(models_[std::size_t(c)], width_, height_, coverage_options_);
    for (const StereoSample& s : samples_) coverage_.back().add(s.views[std::size_t(c)]);
  }
}

int IntrinsicsCollector::jointViews() const {
  int n = 0;
  for (const StereoSample& s : samples_) {
    if (int(s.views[0].corner_ids.size()) >= gates_.min_corners && int(s.views[1].corner_ids.size()) >= gates_.min_corners) {
      ++n;
    }
  }
  return n;
}

std::vector<calib::CameraViews> IntrinsicsCollector::cameraViews(const std::string& model) const {
  std::vector<calib::CameraViews> cameras(2);
  for (int c = 0; c < 2; ++c) {
    calib::CameraViews& v = cameras[std::size_t(c)];
    v.label = c == 0 ? "cam_l" : "cam_r";
    v.model = model;
    v.width = width_;
    v.height = height_;
    for (const StereoSample& s : samples_) {
      const calib::TargetObservation& o = s.views[std::size_t(c)];
      v.views.push_back(int(o.corner_ids.size()) >= gates_.min_corners ? o : calib::TargetObservation{});
    }
  }
  return cameras;
}

}  // namespace telesphere::console::calibration
