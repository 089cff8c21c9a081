// SPDX-License-Identifier: MIT
#include "calib/marker_edge_corners.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

namespace telesphere::calib {
namespace {

/// Bilinear intensity at (x, y), pixel centres at integers; nothing outside the image.
std::optional<double> bilinear(const GrayImage& image, double x, double y) {
  if (!(x >= 0 && y >= 0 && x <= image.width - 1 && y <= image.height - 1)) return std::nullopt;
  const int x0 = std::min(static_cast<int>(x), image.width - 2), y0 = std::min(static_cast<int>(y), image.height - 2);
  const double fx = x - x0, fy = y - y0;
  const double top = (1 - fx) * image.at(x0, y0) + fx * image.at(x0 + 1, y0);
  const double bottom = (1 - fx) * image.at(x0, y0 + 1) + fx * image.at(x0 + 1, y0 + 1);
  return (1 - fy) * top + fy * bottom;
}

/// One side's edge as a curve in the side's own frame: o(s) along the outward normal n at s along
/// d from the side's middle m (s and o in px).
struct SideCurve {
  Eigen::Vector2d m, d, n;
  Eigen::VectorXd coefficients;  ///< o(s) = Σ c_k (s / scale)^k
  double scale = 1;

  double offset(double s) const {
    double o = 0, power = 1;
    for (Eigen::Index k = 0; k < coefficients.size(); ++k, power *= s / scale) o += coefficients[k] * power;
    return o;
  }
  double slope(double s) const {
    double g = 0, power = 1;
    for (Eigen::Index k = 1; k < coefficients.size(); ++k, power *= s / scale) g += double(k) * coefficients[k] * power / scale;
    return g;
  }
  Eigen::Vector2d point(double s) const { return m + s * d + offset(s) * n; }
  Eigen::Vector2d tangent(double s) const { return d + slope(s) * n; }
};

/// The edge's offset along n at p: the centroid of the intensity's rise from the black border
/// (inside) to the paper (outside) within ±w; nothing without a clear rise.
std::optional<double> edgeOffset(const GrayImage& image, const Eigen::Vector2d& p, const Eigen::Vector2d& n, double w) {
  constexpr double kStep = 0.25;  // px between profile samples
  const int steps = static_cast<int>(std::floor(2 * w / kStep));
  std::vector<double> profile;
  profile.reserve(std::size_t(steps) + 1);
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2d q = p + (-w + i * kStep) * n;
    const auto v = bilinear(image, q.x(), q.y());
    if (!v) return std::nullopt;
    profile.push_back(*v);
  }
  // The rise between neighbouring samples, at their middle; the centroid of its upper part (the
  // cut is symmetric about the peak, so a symmetric blur moves nothing).
  double peak = 0;
  for (int i = 0; i < steps; ++i) peak = std::max(peak, profile[std::size_t(i) + 1] - profile[std::size_t(i)]);
  const double rise = profile.back() - profile.front();
  if (rise < 20.0 || peak <= 0) return std::nullopt;  // grey levels: no edge here (shadow, glare, the image rim)
  double sum = 0, sum_o = 0;
  for (int i = 0; i < steps; ++i) {
    const double g = profile[std::size_t(i) + 1] - profile[std::size_t(i)] - 0.2 * peak;
    if (g <= 0) continue;
    sum += g;
    sum_o += g * (-w + (i + 0.5) * kStep);
  }
  return sum_o / sum;
}

/// Least-squares polynomial o(s) through the edge points, one pass without points beyond three
/// median deviations; nothing with too few points.
std::optional<Eigen::VectorXd> fitCurve(const std::vector<Eigen::Vector2d>& points, int degree, double scale, int min_points) {
  std::vector<Eigen::Vector2d> used = points;
  Eigen::VectorXd c;
  for (int pass = 0; pass < 2; ++pass) {
    if (static_cast<int>(used.size()) < std::max(min_points, degree + 2)) return std::nullopt;
    Eigen::MatrixXd A(used.size(), degree + 1);
    Eigen::VectorXd b(used.size());
    for (std::size_t i = 0; i < used.size(); ++i) {
      double power = 1;
      for (int k = 0; k <= degree; ++k, power *= used[i].x() / scale) A(Eigen::Index(i), k) = power;
      b[Eigen::Index(i)] = used[i].y();
    }
    c = A.colPivHouseholderQr().solve(b);
    if (pass == 1) break;
    const Eigen::VectorXd residual = (A * c - b).cwiseAbs();
    std::vector<double> sorted(residual.data(), residual.data() + residual.size());
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
    const double limit = std::max(3.0 * 1.4826 * sorted[sorted.size() / 2], 0.05);
    std::vector<Eigen::Vector2d> kept;
    for (std::size_t i = 0; i < used.size(); ++i)
      if (residual[Eigen::Index(i)] <= limit) kept.push_back(used[i]);
    used.swap(kept);
  }
  return c;
}

}  // namespace

std::optional<std::array<Eigen::Vector2d, 4>> refineMarkerCornersFromEdges(const GrayImage& image,
                                                                          const std::array<Eigen::Vector2d, 4>& initial,
                                                                          const MarkerEdgeOptions& options) {
  const Eigen::Vector2d centre = (initial[0] + initial[1] + initial[2] + initial[3]) / 4.0;
  std::array<SideCurve, 4> sides;
  for (int s = 0; s < 4; ++s) {
    const Eigen::Vector2d& a = initial[std::size_t(s)];
    const Eigen::Vector2d& b = initial[std::size_t((s + 1) % 4)];
    const double length = (b - a).norm();
    const double w = std::min(options.search_half_width_px, 0.4 * length / options.cells_across);
    if (!(length >= 8.0) || w < 1.0) return std::nullopt;  // too small to measure an edge on
    SideCurve& side = sides[std::size_t(s)];
    side.m = (a + b) / 2;
    side.d = (b - a) / length;
    side.n = Eigen::Vector2d(-side.d.y(), side.d.x());
    if (side.n.dot(side.m - centre) < 0) side.n = -side.n;  // outward: from the black border to the paper
    side.scale = length / 2;
    std::vector<Eigen::Vector2d> edge;  // (s, o) in the side's frame
    const int count = std::max(options.min_edge_points, static_cast<int>((options.side_to - options.side_from) * length));
    for (int j = 0; j < count; ++j) {
      const double along = length * (options.side_from + (options.side_to - options.side_from) * (j + 0.5) / count);
      const Eigen::Vector2d p = a + along * side.d;
      if (const auto o = edgeOffset(image, p, side.n, w)) edge.emplace_back(along - length / 2, *o + (p - side.m).dot(side.n));
    }
    const auto c = fitCurve(edge, options.side_degree, side.scale, options.min_edge_points);
    if (!c) return std::nullopt;
    side.coefficients = *c;
  }
  // Corner k is where side k − 1 (ending there) meets side k (starting there): Newton from the
  // initial corner on both curves.
  std::array<Eigen::Vector2d, 4> refined;
  for (int k = 0; k < 4; ++k) {
    const SideCurve& in = sides[std::size_t((k + 3) % 4)];
    const SideCurve& out = sides[std::size_t(k)];
    const Eigen::Vector2d& start = initial[std::size_t(k)];
    double s_in = (start - in.m).dot(in.d), s_out = (start - out.m).dot(out.d);
    bool converged = false;
    for (int iteration = 0; iteration < 20 && !converged; ++iteration) {
      const Eigen::Vector2d f = in.point(s_in) - out.point(s_out);
      Eigen::Matrix2d J;
      J.col(0) = in.tangent(s_in);
      J.col(1) = -out.tangent(s_out);
      if (std::abs(J.determinant()) < 1e-6) return std::nullopt;  // parallel sides: not a marker
      const Eigen::Vector2d step = J.partialPivLu().solve(f);
      s_in -= step.x();
      s_out -= step.y();
      converged = step.norm() < 1e-9;
    }
    refined[std::size_t(k)] = (in.point(s_in) + out.point(s_out)) / 2;
    // The detector's corner is within about a pixel; a refined one far from it fitted something else.
    if (!converged || !((refined[std::size_t(k)] - start).norm() < 2.0)) return std::nullopt;
  }
  return refined;
}

}  // namespace telesphere::calib
