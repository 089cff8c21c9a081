#version 450 core
// SPDX-License-Identifier: MIT
// @brief Full-screen triangle for the exact and look-up-table paths: hands each fragment its
//        eye ray in the camera frame. The ray (tan x, tan y, −1) of the OpenXR view frame is affine
//        in screen position, so interpolating it is exact.

uniform mat3 u_R_cam_eye;  // eye (OpenXR view convention) → camera optical frame
uniform vec4 u_tan;        // tan of the XrFovf angles: left, right, down, up

out vec3 v_ray_cam;

void main() {
  vec2 ndc = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  vec2 f = 0.5 * (ndc + 1.0);
  vec3 ray_eye = vec3(mix(u_tan.x, u_tan.y, f.x), mix(u_tan.z, u_tan.w, f.y), -1.0);
  v_ray_cam = u_R_cam_eye * ray_eye;
  gl_Position = vec4(ndc, 0.0, 1.0);
}
