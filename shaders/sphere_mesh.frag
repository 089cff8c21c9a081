#version 450 core
// SPDX-License-Identifier: MIT
// @brief Mesh path: bilinear sample at the interpolated camera pixel.
#include "sphere_common.glsl"

in vec2 v_px;
out vec4 o_colour;

void main() { o_colour = sampleCamera(v_px); }
