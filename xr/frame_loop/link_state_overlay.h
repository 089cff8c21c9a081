// SPDX-License-Identifier: MIT
/// @brief What the operator must be told about the picture, never left to guess (DESIGN.md §9):
///        - an image older than tint_after_ms (capture → display): an amber border round the view;
///        - older than grey_after_ms: the image loses its colour (the renderer's saturation), the
///          border turns red and "STALE" with the age stands at the top;
///        - a stream below nominal (the media path gave up frame rate, scale or quality for the
///          link): one small line low in the view saying what it runs at ("LINK 8.5M 15HZ 50% Q70");
///        - the robot's camera farther than behind_after_m from the operator's eye (the arm has
///          not caught up): "ROBOT BEHIND YOU";
///        - a link without keys (--insecure, DESIGN.md §10): "INSECURE LINK" in red, always.
///        Drawn after the eye image with scissored clears (hud_text.h), as the trial indicator.
#pragma once

#include <string>

#include "robot/link/telesphere_link.pb.h"
#include "shaders/gl_api.h"

namespace telesphere::xr::frame_loop {

struct LinkStateOptions {
  double tint_after_ms = 250;
  double grey_after_ms = 1000;
  double behind_after_m = 0.15;
};

enum class Staleness { kFresh, kTinted, kStale };

/// One display frame's state.
struct LinkState {
  double image_age_ms = -1;           ///< capture → this display; < 0: no image
  std::string stream_text;            ///< empty: the stream is nominal
  double eye_camera_distance_m = -1;  ///< < 0: unknown
  bool insecure = false;              ///< the link runs without keys (--insecure)
};

Staleness stalenessOf(double image_age_ms, const LinkStateOptions& options);
/// 1 while fresh or tinted, 0 once stale (the image shown grey).
float imageSaturationFor(double image_age_ms, const LinkStateOptions& options);
/// "LINK 8.5M 15HZ 50% Q70" for a stream below nominal; empty for a nominal or unset one.
std::string streamText(const link::proto::StreamState& stream);
bool robotBehind(const LinkState& state, const LinkStateOptions& options);

/// Draws the cues of `state` into `framebuffer` (width × height).
void drawLinkState(GLuint framebuffer, int width, int height, const LinkState& state, const LinkStateOptions& options);

}  // namespace telesphere::xr::frame_loop
