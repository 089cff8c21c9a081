// SPDX-License-Identifier: MIT
/// @brief Head-motion trace analysis and writers (see head_motion_trace.h).
#include "robot/head/head_motion_trace.h"

#include "shaders/png_io.h"


#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>

namespace telesphere::robot {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

/// Time at which `value` crosses v_thr upwards first (first = true) or downwards last.
std::optional<double> crossing(const std::vector<HeadMotionSample>& trace, double v_thr,
                               const std::function<double(const HeadMotionSample&)>& value,
                               bool first) {
  const std::size_t n = trace.size();
  for (std::size_t k = 1; k < n; ++k) {
    const std::size_t i = first ? k : n - k;  // segment [i−1, i]
    const double a = value(trace[i - 1]), b = value(trace[i]);
    const bool crosses = first ? (a < v_thr && b >= v_thr) : (a >= v_thr && b < v_thr);
    if (!crosses) continue;
    const double s = (v_thr - a) / (b - a);
    return trace[i - 1].t_s + s * (trace[i].t_s - trace[i - 1].t_s);
  }
  return std::nullopt;
}

class Canvas {
 public:
  Canvas(int width, int height)
      : width_(width), height_(height),
        pixels_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3, 255) {}

  void set(int x, int y, const Rgb& c) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                           static_cast<std::size_t>(x)) * 3;
    pixels_[i] = c[0];
    pixels_[i + 1] = c[1];
    pixels_[i + 2] = c[2];
  }
  /// Bresenham line, `thick` px wide (vertically).
  void line(int x0, int y0, int x1, int y1, const Rgb& c, int thick = 1) {
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (;;) {
      for (int k = 0; k < thick; ++k) set(x0, y0 + k, c);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) { err += dy; x0 += sx; }
      if (e2 <= dx) { err += dx; y0 += sy; }
    }
  }
  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<std::uint8_t>& pixels() const { return pixels_; }

 private:
  int width_, height_;
  std::vector<std::uint8_t> pixels_;
};

struct Panel {
  int x0, y0, x1, y1;  // pixel box, y0 top
  double t_max, v_max;
  int px(double t) const { return x0 + static_cast<int>(std::lround((x1 - x0) * t / t_max)); }
  int py(double v) const { return y1 - static_cast<int>(std::lround((y1 - y0) * v / v_max)); }
};

void drawPanel(Canvas& canvas, const Panel& p, double grid_step, double t_step) {
  const Rgb grid{225, 225, 225}, axis{0, 0, 0};
  for (double v = grid_step; v < p.v_max; v += grid_step) canvas.line(p.x0, p.py(v), p.x1, p.py(v), grid);
  for (double t = t_step; t < p.t_max; t += t_step) canvas.line(p.px(t), p.y0, p.px(t), p.y1, grid);
  canvas.line(p.x0, p.y1, p.x1, p.y1, axis);
  canvas.line(p.x0, p.y0, p.x0, p.y1, axis);
}

void drawSeries(Canvas& canvas, const Panel& p, const std::vector<HeadMotionSample>& trace,
                const std::function<double(const HeadMotionSample&)>& value, const Rgb& colour) {
  for (std::size_t i = 1; i < trace.size(); ++i) {
    canvas.line(p.px(trace[i - 1].t_s), p.py(std::min(value(trace[i - 1]), p.v_max)),
                p.px(trace[i].t_s), p.py(std::min(value(trace[i]), p.v_max)), colour, 2);
  }
}

}  // namespace

HeadLatencies measureHeadLatencies(const std::vector<HeadMotionSample>& trace, double v_thr) {
  const auto op = [](const HeadMotionSample& s) { return s.v_operator; };
  const auto rob = [](const HeadMotionSample& s) { return s.v_robot; };
  HeadLatencies out;
  const auto op_start = crossing(trace, v_thr, op, true), rob_start = crossing(trace, v_thr, rob, true);
  const auto op_end = crossing(trace, v_thr, op, false), rob_end = crossing(trace, v_thr, rob, false);
  if (op_start && rob_start) out.start_s = *rob_start - *op_start;
  if (op_end && rob_end) out.finish_s = *rob_end - *op_end;
  return out;
}

bool writeHeadMotionCsv(const std::filesystem::path& path,
                        const std::vector<HeadMotionSample>& trace) {
  std::ofstream out(path);
  if (!out) return false;
  out << "t_s,v_operator,v_robot,deviation\n";
  char line[160];
  for (const HeadMotionSample& s : trace) {
    std::snprintf(line, sizeof line, "%.4f,%.6f,%.6f,%.6f\n", s.t_s, s.v_operator, s.v_robot,
                  s.deviation);
    out << line;
  }
  return static_cast<bool>(out);
}

bool writeHeadMotionPng(const std::filesystem::path& path,
                        const std::vector<HeadMotionSample>& trace, int width, int height) {
  if (width < 64 || height < 64 || trace.size() < 2) return false;
  Canvas canvas(width, height);
  double t_max = trace.back().t_s, v_max = 0, d_max = 0;
  for (const HeadMotionSample& s : trace) {
    v_max = std::max({v_max, s.v_operator, s.v_robot});
    d_max = std::max(d_max, s.deviation);
  }
  t_max = std::max(t_max, 1e-3);
  v_max = std::max(1.1 * v_max, 1e-3);
  d_max = std::max(1.1 * d_max, 1e-4);
  const int margin = 20, split = height * 3 / 5;
  const Panel speeds{margin, margin, width - margin, split - margin / 2, t_max, v_max};
  const Panel deviation{margin, split + margin / 2, width - margin, height - margin, t_max, d_max};
  drawPanel(canvas, speeds, 0.1, 0.5);
  drawPanel(canvas, deviation, 0.01, 0.5);
  drawSeries(canvas, speeds, trace, [](const HeadMotionSample& s) { return s.v_operator; },
             Rgb{30, 90, 220});
  drawSeries(canvas, speeds, trace, [](const HeadMotionSample& s) { return s.v_robot; },
             Rgb{220, 40, 30});
  drawSeries(canvas, deviation, trace, [](const HeadMotionSample& s) { return s.deviation; },
             Rgb{20, 150, 60});

  return gl::writePng(path.string(), canvas.width(), canvas.height(), 3, canvas.pixels().data());
}

}  // namespace telesphere::robot
