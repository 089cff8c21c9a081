// SPDX-License-Identifier: MIT
// @brief What every sphere render path shares: the ray–sphere intersection, and sampling the
//        camera image (RGB or float texture, or JPEG-native YUV planes converted here; greyscale
//        is YUV with neutral 1×1 chroma planes) at the image saturation, times the image gain,
//        with the border colour outside the image. TS_SOURCE_YUV selects the YUV planes.
//        TS_DEPTH_GRID replaces the sphere of radius r by the inverse-depth grid proxy
//        (xr/render/depth_proxy.h): a march to the first crossing, TS_GRID_STEPS refinements.

uniform vec4 u_border;      // colour of pixels the camera did not see
uniform vec2 u_image_size;  // camera image width, height (px)
uniform float u_image_gain; // the camera image's brightness factor (1: as captured)
uniform float u_image_saturation;  // its colour (0: grey, 1: as captured)

#if TS_SOURCE_YUV
layout(binding = 0) uniform sampler2D u_plane_y;  // full size
layout(binding = 1) uniform sampler2D u_plane_u;  // Cb, subsampled
layout(binding = 2) uniform sampler2D u_plane_v;  // Cr, subsampled
#else
layout(binding = 0) uniform sampler2D u_image;
#endif

// The far (larger) root t of |o + t·d| = r for a unit d, written without cancellation:
// t = s − b for b ≤ 0, t = −c/(b + s) otherwise, with b = o·d, c = |o|² − r², s = sqrt(b² − c).
// Inside the sphere that is the only root ahead; outside it is the far side (the sphere's inside
// surface seen through it). No hit (miss, or the sphere behind the eye): false.
bool sphereFarHit(vec3 o, vec3 d, float c, out vec3 p) {
  float b = dot(o, d);
  float disc = b * b - c;
  p = vec3(0.0);
  if (!(disc >= 0.0)) return false;
  float s = sqrt(disc);
  float t = b <= 0.0 ? s - b : -c / (b + s);
  if (!(t >= 0.0)) return false;
  p = o + t * d;
  return true;
}

uniform vec3 u_origin_cam;  // eye position in the camera frame (m); zero in orientation3d
uniform float u_sphere_c;   // |origin|² − r², computed in double on the CPU

#if TS_DEPTH_GRID
// Inverse depth (1/m) per tile, cols × rows texels: longitude λ = atan(x, z) along s (repeating
// round the seam), latitude asin(−y) along t (clamped at the poles); texel centres are tile
// centres. The four texels around a direction, interpolated bilinearly, or the closest of them
// where they span more than u_edge_jump (a depth edge): the CPU's
// InverseDepthGrid::sampleKeepingEdges (GridEdgeTile::kClosest).
layout(binding = 4) uniform sampler2D u_inverse_depth;
uniform vec2 u_radius_range;  // kMinProxyRadiusM, kMaxProxyRadiusM
uniform float u_edge_jump;    // RenderSettings::grid_edge_slope_per_m_per_deg × the tile size (1/m)

float proxyRadius(vec3 dir) {
  const float pi = 3.14159265358979;
  float lat = asin(clamp(-dir.y / length(dir), -1.0, 1.0));
  float lon = atan(dir.x, dir.z);
  // Continuous texel coordinates with texel centres at integers. The four texels come from one
  // textureGather at the middle of their 2×2 block (texel coordinates base + 1), where no GPU's
  // rounding of the coordinate can pick another block than the weights f assume; the texture's
  // wrap modes do the seam (repeat) and the poles (clamp to edge).
  vec2 size = vec2(textureSize(u_inverse_depth, 0));
  vec2 st = vec2((lon + pi) / (2.0 * pi), (lat + 0.5 * pi) / pi) * size - 0.5;
  vec2 base = floor(st), f = st - base;
  vec4 q = textureGather(u_inverse_depth, (base + 1.0) / size, 0);  // (c0, r1), (c1, r1), (c1, r0), (c0, r0)
  float v00 = q.w, v01 = q.z, v10 = q.x, v11 = q.y;
  float hi = max(max(v00, v01), max(v10, v11)), lo = min(min(v00, v01), min(v10, v11));
  float closest = f.y < 0.5 ? (f.x < 0.5 ? v00 : v01) : (f.x < 0.5 ? v10 : v11);
  float rho = hi - lo > u_edge_jump ? closest : mix(mix(v00, v01, f.x), mix(v10, v11, f.x), f.y);
  return rho > 1.0 / u_radius_range.y ? clamp(1.0 / rho, u_radius_range.x, u_radius_range.y) : u_radius_range.y;
}
#endif

#if TS_DEPTH_GRID
uniform vec2 u_rho_range;        // the march's inverse depths (1/m): 1/kMaxProxyRadiusM, the grid's largest value
uniform float u_march_step_rad;  // the most a march step moves the ray's point as the camera sees it

// The ray's point at inverse depth rho from the camera (the far root of |o + t·d| = 1/rho) and
// the grid's inverse depth there minus rho (negative in front of the surface). False: not reached.
bool marchPoint(vec3 o, vec3 d, float rho, out vec3 p, out float g) {
  g = 0.0;
  if (!sphereFarHit(o, d, dot(o, o) - 1.0 / (rho * rho), p)) return false;
  g = 1.0 / proxyRadius(p) - rho;
  return true;
}
#endif

// The point on the scene proxy an eye ray (from o, unit d) shows: the far sphere hit, or with the
// grid where the ray first meets it (gridProxyHit): a march in the inverse depth of the ray's
// point from the grid's largest value down, in steps that move the point by at most
// u_march_step_rad as the camera sees it, then TS_GRID_STEPS bisections of the step that crossed and
// the point where g, linear between the bracket's ends, is 0. Without the march (TS_GRID_MARCH 0),
// TS_GRID_STEPS fixed-point steps from the ray's own direction. False where the ray does not reach
// the proxy.
bool proxyHit(vec3 o, vec3 d, out vec3 p) {
#if TS_DEPTH_GRID
#if !TS_GRID_MARCH
  float r = proxyRadius(d);
  if (!sphereFarHit(o, d, dot(o, o) - r * r, p)) return false;
  for (int k = 0; k < TS_GRID_STEPS; ++k) {
    r = proxyRadius(p);
    if (!sphereFarHit(o, d, dot(o, o) - r * r, p)) return false;
  }
  return true;
#else
  float top = u_rho_range.y, bottom = u_rho_range.x;
  float a = top, ga;
  vec3 pa;
  bool has_a = marchPoint(o, d, a, pa, ga);
  if (has_a && ga >= 0.0) {
    p = pa;
    return true;
  }
  int n = int(clamp(ceil(length(cross(o, d)) * (top - bottom) / u_march_step_rad), 1.0, float(TS_GRID_MARCH_MAX)));
  // The march only brackets; the bisections follow the loop, so that rays crossing at different
  // steps do not each hold up their neighbours with a bisection of their own.
  float b = top, gb = 0.0;
  bool crossed = false;
  for (int k = 1; k <= n; ++k) {
    b = k == n ? bottom : mix(top, bottom, float(k) / float(n));
    vec3 pb;
    bool has_b = marchPoint(o, d, b, pb, gb);
    if (has_b && (gb >= 0.0 || k == n)) {  // at the far bound: nothing lies beyond (a division may round g below 0)
      crossed = true;
      break;
    }
    a = b;
    ga = gb;
    has_a = has_b;
  }
  if (!crossed || !has_a) return false;  // the ray passes outside the surface
  for (int s = 0; s < TS_GRID_STEPS; ++s) {
    float c = 0.5 * (a + b), gc;
    vec3 pc;
    if (!marchPoint(o, d, c, pc, gc)) break;
    if (gc >= 0.0) {
      b = c;
      gb = gc;
    } else {
      a = c;
      ga = gc;
    }
  }
  float rho = a + ga * (b - a) / (ga - gb);
  return sphereFarHit(o, d, dot(o, o) - 1.0 / (rho * rho), p);
#endif
#else
  return sphereFarHit(o, d, u_sphere_c, p);
#endif
}

// Bilinear sample at camera pixel px (origin at the centre of the top-left pixel); the border
// colour outside [−0.5, W − 0.5] × [−0.5, H − 0.5].
vec4 sampleCamera(vec2 px) {
  if (any(lessThan(px, vec2(-0.5))) || any(greaterThan(px, u_image_size - 0.5))) return u_border;
  vec2 uv = (px + 0.5) / u_image_size;
#if TS_SOURCE_YUV
  // JFIF full-range BT.601, chroma centred between luma samples (what libjpeg decodes).
  float y = texture(u_plane_y, uv).r;
  float cb = texture(u_plane_u, uv).r - 128.0 / 255.0;
  float cr = texture(u_plane_v, uv).r - 128.0 / 255.0;
  vec3 rgb = clamp(vec3(y + 1.402 * cr, y - 0.344136 * cb - 0.714136 * cr, y + 1.772 * cb), 0.0, 1.0);
  float luma = dot(rgb, vec3(0.299, 0.587, 0.114));
  return vec4(u_image_gain * mix(vec3(luma), rgb, u_image_saturation), 1.0);
#else
  vec4 c = texture(u_image, uv);
  float luma = dot(c.rgb, vec3(0.299, 0.587, 0.114));
  return vec4(u_image_gain * mix(vec3(luma), c.rgb, u_image_saturation), c.a);
#endif
}
