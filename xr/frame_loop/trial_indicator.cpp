// SPDX-License-Identifier: MIT
/// @brief The trial indicator bar (see trial_indicator.h).
#include "xr/frame_loop/trial_indicator.h"

#include <algorithm>
#include <cmath>

namespace telesphere::xr::frame_loop {

TrialIndicatorGeometry trialIndicatorGeometry(int width, int height) {
  TrialIndicatorGeometry g;
  g.width = std::max(8, int(std::lround(0.24 * width)));
  g.height = std::max(3, int(std::lround(0.008 * height)));
  g.x = (width - g.width) / 2;
  g.y = int(std::lround(0.22 * height));  // low in the view, clear of the lens edge
  return g;
}

double trialIndicatorFill(double elapsed_s, double time_limit_s) {
  if (!(elapsed_s > 0.0)) return 0.0;
  if (time_limit_s > 0.0) return std::min(1.0, elapsed_s / time_limit_s);
  return std::fmod(elapsed_s, 60.0) / 60.0;
}

void drawTrialIndicator(GLuint framebuffer, int width, int height, double elapsed_s, double time_limit_s) {
  const TrialIndicatorGeometry g = trialIndicatorGeometry(width, height);
  const auto box = [](int x, int y, int w, int h, float r, float gr, float b) {
    if (w <= 0 || h <= 0) return;
    glScissor(x, y, w, h);
    glClearColor(r, gr, b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
  };
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glEnable(GL_SCISSOR_TEST);
  const int border = std::max(1, g.height / 4);
  box(g.x - border, g.y - border, g.width + 2 * border, g.height + 2 * border, 0.05f, 0.05f, 0.05f);
  box(g.x, g.y, g.width, g.height, 0.25f, 0.25f, 0.25f);
  const int filled = int(std::lround(trialIndicatorFill(elapsed_s, time_limit_s) * g.width));
  const bool over = time_limit_s > 0.0 && elapsed_s >= time_limit_s;
  const bool last_minute = time_limit_s > 0.0 && elapsed_s >= time_limit_s - std::min(60.0, 0.2 * time_limit_s);
  if (over)
    box(g.x, g.y, filled, g.height, 0.85f, 0.15f, 0.1f);
  else if (last_minute)
    box(g.x, g.y, filled, g.height, 0.95f, 0.65f, 0.1f);
  else
    box(g.x, g.y, filled, g.height, 0.2f, 0.75f, 0.3f);
  if (time_limit_s >= 60.0)  // a gap at every full minute
    for (int minute = 1; minute * 60.0 < time_limit_s; ++minute) {
      const int x = g.x + int(std::lround(minute * 60.0 / time_limit_s * g.width));
      box(x, g.y, std::max(1, g.height / 3), g.height, 0.05f, 0.05f, 0.05f);
    }
  glDisable(GL_SCISSOR_TEST);
}

}  // namespace telesphere::xr::frame_loop
