// SPDX-License-Identifier: MIT
/// @brief The study's trial indicator in the operator's view (paper §IV-B; issue: "the operator
///        can see in the headset that a trial is running and how long it has run, small and
///        unobtrusive"): a thin bar low in each eye's view, 24 % of its width, filling with the
///        elapsed share of the time limit, with a gap at every full minute; green, amber in the
///        last minute (the last fifth of shorter limits), red once the limit has passed.
///        Without a time limit the bar sweeps once a minute. Drawn after the eye image with a few
///        scissored clears (no shader, no GL state left behind).
#pragma once

#include "shaders/gl_api.h"

namespace telesphere::xr::frame_loop {

struct TrialIndicatorGeometry {
  int x = 0, y = 0, width = 0, height = 0;  ///< GL window coordinates (origin bottom left)
};

/// Where the bar goes in a `width` × `height` eye image.
TrialIndicatorGeometry trialIndicatorGeometry(int width, int height);

/// The filled share of the bar for `elapsed_s` of `time_limit_s` (0: no limit), 0…1.
double trialIndicatorFill(double elapsed_s, double time_limit_s);

/// Draws the bar into `framebuffer`.
void drawTrialIndicator(GLuint framebuffer, int width, int height, double elapsed_s, double time_limit_s);

}  // namespace telesphere::xr::frame_loop
