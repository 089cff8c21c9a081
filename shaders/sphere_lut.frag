#version 450 core
// SPDX-License-Identifier: MIT
// @brief Look-up-table path: eye ray → far sphere hit (or the grid proxy's point) → direction from the camera centre →
//        camera pixel from a precomputed direction→pixel texture → bilinear sample. The table is
//        indexed by the azimuthal equidistant projection about the optical axis (θ/π·(cos φ,
//        sin φ) mapped to [0, 1]²), so it covers the whole sphere of directions; validity is the
//        model's own θ < maxAngle() test, exact per fragment.
#include "sphere_common.glsl"

uniform float u_max_angle;  // the camera model's maxAngle() (rad)
layout(binding = 3) uniform sampler2D u_lut;  // RG32F camera pixel per direction

in vec3 v_ray_cam;
out vec4 o_colour;

void main() {
  vec3 p;
  if (!proxyHit(u_origin_cam, normalize(v_ray_cam), p)) {
    o_colour = u_border;
    return;
  }
  float rxy = length(p.xy);
  float theta = atan(rxy, p.z);
  if (!(theta < u_max_angle)) {
    o_colour = u_border;
    return;
  }
  vec2 q = rxy > 0.0 ? p.xy * (theta / (3.14159265358979 * rxy)) : vec2(0.0);
  o_colour = sampleCamera(texture(u_lut, 0.5 + 0.5 * q).rg);
}
