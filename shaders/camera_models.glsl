// SPDX-License-Identifier: MIT
// @brief The camera models of calib/ in GLSL (float), one per TS_MODEL: 0 ds, 1 eucm, 2 kb4,
//        3 pinhole. Same formulas and validity as the C++ headers; u_cam_limit is the bound the
//        C++ object computed (ds: w2 = −cos(maxAngle()), eucm: w, kb4: θmax, pinhole: r²max).
//        projectCamera(p_cam, out px): p_cam in the camera optical frame (x right, y down,
//        z forward), px in pixels with the origin at the centre of the top-left pixel.

uniform float u_cam[8];     // parameters in kalibr/Basalt order [fx, fy, cx, cy, ...]
uniform float u_cam_limit;  // see above

#if TS_MODEL == 0
// Double sphere [fx, fy, cx, cy, xi, alpha]: valid iff z > −w2·|p| and den > 0.
bool projectCamera(vec3 p, out vec2 px) {
  px = vec2(0.0);
  float d1 = length(p);
  if (!(p.z > -u_cam_limit * d1)) return false;
  float k = u_cam[4] * d1 + p.z;
  float d2 = sqrt(dot(p.xy, p.xy) + k * k);
  float den = u_cam[5] * d2 + (1.0 - u_cam[5]) * k;
  if (!(den > 0.0)) return false;
  px = vec2(u_cam[0], u_cam[1]) * (p.xy / den) + vec2(u_cam[2], u_cam[3]);
  return true;
}
#elif TS_MODEL == 1
// Extended unified [fx, fy, cx, cy, alpha, beta]: valid iff z > −w·rho and den > 0.
bool projectCamera(vec3 p, out vec2 px) {
  px = vec2(0.0);
  float rho = sqrt(u_cam[5] * dot(p.xy, p.xy) + p.z * p.z);
  if (!(p.z > -u_cam_limit * rho)) return false;
  float den = u_cam[4] * rho + (1.0 - u_cam[4]) * p.z;
  if (!(den > 0.0)) return false;
  px = vec2(u_cam[0], u_cam[1]) * (p.xy / den) + vec2(u_cam[2], u_cam[3]);
  return true;
}
#elif TS_MODEL == 2
// Kannala-Brandt KB4 [fx, fy, cx, cy, k1, k2, k3, k4]: valid iff θ < θmax.
bool projectCamera(vec3 p, out vec2 px) {
  px = vec2(0.0);
  float r = length(p.xy);
  float theta = atan(r, p.z);
  if (!(theta < u_cam_limit)) return false;
  float t2 = theta * theta;
  // θ/r, with its limit 1/z on the axis.
  float q = r > 1e-6 * abs(p.z) ? theta / r : 1.0 / p.z;
  float poly = 1.0 + t2 * (u_cam[4] + t2 * (u_cam[5] + t2 * (u_cam[6] + t2 * u_cam[7])));
  px = vec2(u_cam[0], u_cam[1]) * (p.xy * (q * poly)) + vec2(u_cam[2], u_cam[3]);
  return true;
}
#elif TS_MODEL == 3
// Pinhole + radtan [fx, fy, cx, cy, k1, k2, p1, p2]: valid iff z > 0 and r² < r²max.
bool projectCamera(vec3 p, out vec2 px) {
  px = vec2(0.0);
  if (!(p.z > 0.0)) return false;
  vec2 ab = p.xy / p.z;
  float r2 = dot(ab, ab);
  if (!(r2 < u_cam_limit)) return false;
  float radial = 1.0 + r2 * (u_cam[4] + r2 * u_cam[5]);
  float ab2 = 2.0 * ab.x * ab.y;
  vec2 d = vec2(ab.x * radial + u_cam[6] * ab2 + u_cam[7] * (r2 + 2.0 * ab.x * ab.x),
                ab.y * radial + u_cam[6] * (r2 + 2.0 * ab.y * ab.y) + u_cam[7] * ab2);
  px = vec2(u_cam[0], u_cam[1]) * d + vec2(u_cam[2], u_cam[3]);
  return !(isinf(px.x) || isinf(px.y) || isnan(px.x) || isnan(px.y));
}
#else
#error "TS_MODEL must be 0 (ds), 1 (eucm), 2 (kb4) or 3 (pinhole)"
#endif
