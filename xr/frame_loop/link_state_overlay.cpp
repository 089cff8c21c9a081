// SPDX-License-Identifier: MIT
/// @brief The link's cues in the operator's view (see link_state_overlay.h).
#include "xr/frame_loop/link_state_overlay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "xr/frame_loop/hud_text.h"

namespace telesphere::xr::frame_loop {

Staleness stalenessOf(double age_ms, const LinkStateOptions& o) {
  if (!(age_ms >= o.tint_after_ms)) return Staleness::kFresh;
  return age_ms >= o.grey_after_ms ? Staleness::kStale : Staleness::kTinted;
}

float imageSaturationFor(double age_ms, const LinkStateOptions& o) {
  return stalenessOf(age_ms, o) == Staleness::kStale ? 0.0f : 1.0f;
}

std::string streamText(const link::proto::StreamState& s) {
  if (!s.adapted()) return {};
  char text[64];
  std::snprintf(text, sizeof text, "LINK %.1fM %.0fHZ %.0f%% Q%u", s.target_mbit(), s.fps(), 100.0 * s.scale(),
                s.quality());
  return text;
}

bool robotBehind(const LinkState& state, const LinkStateOptions& o) {
  return state.eye_camera_distance_m >= 0 && state.eye_camera_distance_m > o.behind_after_m;
}

void drawLinkState(GLuint framebuffer, int width, int height, const LinkState& state, const LinkStateOptions& o) {
  const Staleness staleness = stalenessOf(state.image_age_ms, o);
  const bool behind = robotBehind(state, o);
  if (staleness == Staleness::kFresh && state.stream_text.empty() && !behind && !state.insecure) return;
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  const int side = std::min(width, height);
  // Text about 1.6 % of the view high: readable in a headset, small on a desktop mirror.
  const int scale = std::max(1, side / 450);
  if (staleness != Staleness::kFresh) {
    const int t = std::max(2, side / 60);
    const bool stale = staleness == Staleness::kStale;
    glEnable(GL_SCISSOR_TEST);
    glClearColor(stale ? 0.85f : 0.95f, stale ? 0.15f : 0.6f, stale ? 0.1f : 0.1f, 1.0f);
    for (const auto& [x, y, w, h] : {std::array<int, 4>{0, 0, width, t}, std::array<int, 4>{0, height - t, width, t},
                                     std::array<int, 4>{0, 0, t, height}, std::array<int, 4>{width - t, 0, t, height}}) {
      glScissor(x, y, w, h);
      glClear(GL_COLOR_BUFFER_BIT);
    }
    glDisable(GL_SCISSOR_TEST);
    if (stale) {
      char text[32];
      std::snprintf(text, sizeof text, "STALE %.1fS", state.image_age_ms * 1e-3);
      const int big = 2 * scale;
      drawHudText(text, (width - hudTextWidth(text, big)) / 2, height - 3 * t - kGlyphRows * big, big, 0.95f, 0.2f,
                  0.15f);
    }
  }
  if (behind) {
    const std::string text = "ROBOT BEHIND YOU";
    drawHudText(text, (width - hudTextWidth(text, 2 * scale)) / 2, height / 3, 2 * scale, 0.95f, 0.65f, 0.1f);
  }
  if (state.insecure) {
    const std::string text = "INSECURE LINK";
    drawHudText(text, (width - hudTextWidth(text, scale)) / 2, static_cast<int>(0.12 * height), scale, 0.95f, 0.15f,
                0.1f);
  }
  if (!state.stream_text.empty())
    drawHudText(state.stream_text, (width - hudTextWidth(state.stream_text, scale)) / 2,
                static_cast<int>(0.16 * height), scale, 0.85f, 0.85f, 0.85f);
}

}  // namespace telesphere::xr::frame_loop
