// SPDX-License-Identifier: MIT
/// @brief DepthProxySeries: the XR app's scene proxy state → series.
#include "console/telemetry/depth_proxy_series.h"

#include <cmath>
#include <cstring>

namespace telesphere::console::telemetry {
namespace {

constexpr double kBatchGapS = 1.0;  ///< the XR app's batches come every 100 ms

}  // namespace

std::optional<SeriesInfo> DepthProxySeries::infoOf(const char* name) {
  static const struct {
    const char* name;
    const char* label;
    const char* unit;
  } kInfo[] = {
      {series::kDepthRadiusLeftM, "scene radius, left eye", "m"},
      {series::kDepthRadiusRightM, "scene radius, right eye", "m"},
      {series::kDepthMatchedLeftPct, "stereo tiles matched, left camera", "%"},
      {series::kDepthMatchedRightPct, "stereo tiles matched, right camera", "%"},
      {series::kDepthAgeMs, "depth age (capture → in use)", "ms"},
      {series::kDepthSweepMs, "depth sweep CPU time per pair", "ms"},
  };
  for (const auto& i : kInfo)
    if (std::strcmp(i.name, name) == 0) return SeriesInfo{i.name, i.label, i.unit};
  return std::nullopt;
}

DepthProxySeries::DepthProxySeries(SeriesStore& store) {
  const auto make = [&](const char* name) { return &store.series(*infoOf(name), kBatchGapS); };
  radius_[0] = make(series::kDepthRadiusLeftM);
  radius_[1] = make(series::kDepthRadiusRightM);
  matched_[0] = make(series::kDepthMatchedLeftPct);
  matched_[1] = make(series::kDepthMatchedRightPct);
  age_ = make(series::kDepthAgeMs);
  sweep_ = make(series::kDepthSweepMs);
}

std::size_t DepthProxySeries::add(const link::proto::DepthProxyState& s, double t) {
  std::size_t n = 0;
  const auto add = [&](TimeSeries* series, double v) {
    if (!std::isfinite(v)) return;  // a peer's nonsense is not plotted
    series->append(t, v);
    ++n;
  };
  for (int i = 0; i < 2 && i < s.radius_m_size(); ++i) add(radius_[i], s.radius_m(i));
  for (int i = 0; i < 2 && i < s.matched_fraction_size(); ++i) add(matched_[i], s.matched_fraction(i) * 100.0);
  if (s.estimate_age_ms() >= 0.0) {
    add(age_, s.estimate_age_ms());
    add(sweep_, s.sweep_ms());
  }
  return n;
}

}  // namespace telesphere::console::telemetry
