#version 450 core
// SPDX-License-Identifier: MIT
// @brief Mesh path: a tessellated sphere around the camera whose vertices carry their camera
//        pixel (projected once, in double, on the CPU); the rasteriser interpolates the pixel.

layout(location = 0) in vec3 a_dir_cam;  // unit direction from the camera centre
layout(location = 1) in vec2 a_px;       // its camera pixel

uniform mat4 u_clip_from_sphere;  // projection · T_eye_cam · scale(r)

out vec2 v_px;

void main() {
  v_px = a_px;
  gl_Position = u_clip_from_sphere * vec4(a_dir_cam, 1.0);
}
