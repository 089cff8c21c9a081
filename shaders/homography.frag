#version 450 core
// SPDX-License-Identifier: MIT
// @brief Planar reprojection through a homography, one bilinear sample per pixel: what a
//        runtime's planar timewarp costs, the floor the sphere paths are measured against.
layout(binding = 0) uniform sampler2D u_image;
uniform mat3 u_H;  // window pixel (x, y, 1) → normalised texture coordinate (homogeneous)
out vec4 o_colour;

void main() {
  vec3 p = u_H * vec3(gl_FragCoord.xy, 1.0);
  o_colour = texture(u_image, p.xy / p.z);
}
