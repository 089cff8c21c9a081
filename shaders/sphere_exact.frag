#version 450 core
// SPDX-License-Identifier: MIT
// @brief Exact path: per fragment, eye ray → far sphere hit → camera model → bilinear sample.
#include "sphere_common.glsl"
#include "camera_models.glsl"

uniform vec3 u_origin_cam;  // eye position in the camera frame (m); zero in orientation3d
uniform float u_sphere_c;   // |origin|² − r², computed in double on the CPU

in vec3 v_ray_cam;
out vec4 o_colour;

void main() {
  vec3 p;
  vec2 px;
  if (!sphereFarHit(u_origin_cam, normalize(v_ray_cam), u_sphere_c, p) || !projectCamera(p, px)) {
    o_colour = u_border;
    return;
  }
  o_colour = sampleCamera(px);
}
