// SPDX-License-Identifier: MIT
/// @brief The per-tile temporal filter of inverse depth: exponential average, snap, rate limit.
#include "xr/depth/inverse_depth_filter.h"

#include <algorithm>
#include <cmath>

namespace telesphere::xr::depth {

const render::InverseDepthGrid& InverseDepthFilter::update(const render::InverseDepthGrid& measured,
                                                           const std::vector<float>& confidence, std::int64_t t_ns) {
  snapped_ = 0;
  const bool restart = !state_ || state_->rows() != measured.rows() || state_->cols() != measured.cols() ||
                       t_ns < last_ns_;
  if (restart) {
    state_ = measured;
    last_ns_ = t_ns;
    return *state_;
  }
  const double dt = static_cast<double>(t_ns - last_ns_) * 1e-9;
  last_ns_ = t_ns;
  const double alpha_matched = 1.0 - std::exp(-dt / std::max(options_.time_constant_s, 1e-6));
  const double max_step = options_.max_rate_per_m_s * dt;
  for (int row = 0; row < measured.rows(); ++row)
    for (int col = 0; col < measured.cols(); ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * measured.cols() + col;
      const bool matched = i < confidence.size() && confidence[i] > 0.0F;
      const double now = state_->at(row, col), target = measured.at(row, col);
      if (!std::isfinite(target)) continue;
      const double jump = target - now;
      if (matched && std::abs(jump) > options_.snap_per_m) {
        state_->at(row, col) = static_cast<float>(target);
        ++snapped_;
        continue;
      }
      const double alpha = matched ? alpha_matched : alpha_matched * options_.unconfident_weight;
      const double step = std::clamp(alpha * jump, -max_step, max_step);
      state_->at(row, col) = static_cast<float>(std::max(0.0, now + step));
    }
  return *state_;
}

}  // namespace telesphere::xr::depth
