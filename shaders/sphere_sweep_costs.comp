#version 450 core
// The sphere sweep's pair costs on the GPU (#35, xr/depth/gpu_sweep_costs.h): one invocation per
// tile and inverse-depth hypothesis, 1 − ZNCC of the tile's reference patch (mean-free values and
// their Σa², from the CPU) against the other image's patch at that hypothesis. The bilinear samples
// are the CPU's (xr/depth/bilinear_tap.h: integer weights in 1/256, so every sample is equal), less
// 128 as the CPU sums them (less cancellation in the variance); the
// sums add in sample order, where the CPU's AVX2 sums add eight lanes at a time, so a cost may
// differ in its last bits.
layout(local_size_x = 64) in;

// Per tile (the sweep's order), per hypothesis, per sample: x | y << 16, wx | wy << 16.
layout(std430, binding = 0) readonly buffer OtherTaps { uvec2 other_taps[]; };
// Per tile, per sample: the reference patch's mean-free grey values.
layout(std430, binding = 1) readonly buffer ReferencePatches { float reference_a[]; };
// Per tile: Σa² of its patch.
layout(std430, binding = 2) readonly buffer ReferenceEnergy { float reference_aa[]; };
// Per tile, per hypothesis: 1 − ZNCC, infinity where the other patch has no texture.
layout(std430, binding = 3) writeonly buffer Costs { float costs[]; };

layout(binding = 0) uniform usampler2D other_image;  // R8UI, the other camera's grey image
layout(location = 0) uniform int tiles;
layout(location = 1) uniform int hypotheses;
layout(location = 2) uniform int samples;

void main() {
  const uint index = gl_GlobalInvocationID.x;  // tile · hypotheses + hypothesis
  if (index >= uint(tiles * hypotheses)) return;
  const uint tile = index / uint(hypotheses);
  const uint first_tap = index * uint(samples), first_a = tile * uint(samples);
  float sum_b = 0.0, sum_bb = 0.0, sum_ab = 0.0;
  for (int s = 0; s < samples; ++s) {
    const uvec2 t = other_taps[first_tap + uint(s)];
    const ivec2 p = ivec2(int(t.x & 0xFFFFu), int(t.x >> 16));
    const uint wx = t.y & 0xFFFFu, wy = t.y >> 16;
    const uint p00 = texelFetch(other_image, p, 0).r, p01 = texelFetch(other_image, p + ivec2(1, 0), 0).r;
    const uint p10 = texelFetch(other_image, p + ivec2(0, 1), 0).r, p11 = texelFetch(other_image, p + ivec2(1, 1), 0).r;
    const uint top = p00 * (256u - wx) + p01 * wx, bottom = p10 * (256u - wx) + p11 * wx;
    // b − kPatchGreyOffset (xr/depth/patch_sums.h; TS_GREY_OFFSET_FIXED is it · 65536, defined by
    // gpu_sweep_costs.cpp), exact: |value| below 2^24.
    const float b = float(int(top * (256u - wy) + bottom * wy) - TS_GREY_OFFSET_FIXED) * (1.0 / 65536.0);
    sum_b += b;
    sum_bb += b * b;
    sum_ab += reference_a[first_a + uint(s)] * b;
  }
  const float var_b = sum_bb - sum_b * sum_b * (1.0 / float(samples));
  costs[index] = var_b <= 1e-6 ? uintBitsToFloat(0x7F800000u) : 1.0 - sum_ab / sqrt(reference_aa[tile] * var_b);
}
