#version 450 core
// SPDX-License-Identifier: MIT
// @brief Exact path: per fragment, eye ray → far sphere hit (or the grid proxy's point) → camera
//        model → bilinear sample.
#include "sphere_common.glsl"
#include "camera_models.glsl"

in vec3 v_ray_cam;
out vec4 o_colour;

void main() {
  vec3 p;
  vec2 px;
  if (!proxyHit(u_origin_cam, normalize(v_ray_cam), p) || !projectCamera(p, px)) {
    o_colour = u_border;
    return;
  }
  o_colour = sampleCamera(px);
}
