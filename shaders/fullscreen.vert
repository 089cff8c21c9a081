#version 450 core
// SPDX-License-Identifier: MIT
// @brief A full-screen triangle and nothing else (for passes that work from gl_FragCoord).
void main() {
  gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0);
}
