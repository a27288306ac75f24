#version 450
// One Gaussian pass of the fitted-kernel exposure (include/vpsim/exposure/exposure_engine.h),
// specialised by AXIS: along x (0) from the zero-padded deposit into the pass buffer, or along
// y (1) from the pass buffer, ending with the print-through step R = B + a R into the running sum.
//
// Shaped for lavapipe like exposure_stencil.comp (docs/PLATFORM.md): each invocation sums 8
// consecutive outputs along the pass's axis in 8 named accumulators over a window of 8 source
// texels sliding along it, so each tap (a uniform-block load, the same for every lane) feeds 8
// multiply-adds and each texel fetch (one vector gather) 8 more. The source is zero-padded by
// HALF_WIDTH cells along the axis, so no fetch needs a bounds check and every sum runs over the
// taps in the CPU loop's order; the taps are the CPU path's own values (no exp() per tap), and
// HALF_WIDTH is a specialisation constant, so the tap loop has a fixed count.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const int HALF_WIDTH = 1;
layout(constant_id = 1) const uint AXIS = 0u;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"

layout(push_constant) uniform Push { ExposureBlurParams params; };
layout(binding = 0) uniform samplerBuffer source;
layout(std140, binding = 1) uniform Taps { vec4 taps[EXPOSURE_TAP_BLOCK / 4]; };
layout(std430, binding = 2) buffer Target { float target[]; };

void main() {
    // x: outputs (i .. i + 7, j); y: outputs (i, j .. j + 7). Both read the source from texel
    // j * sourceWidth + i on: the deposit's row j starts HALF_WIDTH texels in, and the pass
    // buffer's row j + HALF_WIDTH holds grid row j.
    const bool alongX = AXIS == 0u;
    const int i = int(gl_GlobalInvocationID.x) * (alongX ? 8 : 1);
    const int j = int(gl_GlobalInvocationID.y) * (alongX ? 1 : 8);
    const int step = alongX ? 1 : int(params.sourceWidth);
    const int at = j * int(params.sourceWidth) + i;
    float a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0, a4 = 0.0, a5 = 0.0, a6 = 0.0, a7 = 0.0;
    float d0 = texelFetch(source, at).r, d1 = texelFetch(source, at + step).r;
    float d2 = texelFetch(source, at + 2 * step).r, d3 = texelFetch(source, at + 3 * step).r;
    float d4 = texelFetch(source, at + 4 * step).r, d5 = texelFetch(source, at + 5 * step).r;
    float d6 = texelFetch(source, at + 6 * step).r, d7 = texelFetch(source, at + 7 * step).r;
    for (int t = 0; t <= 2 * HALF_WIDTH; ++t) {
        const float w = taps[t >> 2][t & 3];
        a0 += w * d0; a1 += w * d1; a2 += w * d2; a3 += w * d3;
        a4 += w * d4; a5 += w * d5; a6 += w * d6; a7 += w * d7;
        d0 = d1; d1 = d2; d2 = d3; d3 = d4; d4 = d5; d5 = d6; d6 = d7;
        d7 = texelFetch(source, at + (t + 8) * step).r;
    }
    const float norm = params.norm;
    if (alongX) {
        // Every row of the padded pass buffer is written whole (its rows are a multiple of 8).
        const int o = (j + HALF_WIDTH) * int(params.targetWidth) + i;
        target[o + 0] = a0 / norm; target[o + 1] = a1 / norm;
        target[o + 2] = a2 / norm; target[o + 3] = a3 / norm;
        target[o + 4] = a4 / norm; target[o + 5] = a5 / norm;
        target[o + 6] = a6 / norm; target[o + 7] = a7 / norm;
        return;
    }
    const int nx = int(params.nx), ny = int(params.ny), o = j * nx + i;
    const float a = params.decay;
    if (i >= nx) return;
    if (j + 0 < ny) target[o + 0 * nx] = printThroughStep(a0 / norm, target[o + 0 * nx], a);
    if (j + 1 < ny) target[o + 1 * nx] = printThroughStep(a1 / norm, target[o + 1 * nx], a);
    if (j + 2 < ny) target[o + 2 * nx] = printThroughStep(a2 / norm, target[o + 2 * nx], a);
    if (j + 3 < ny) target[o + 3 * nx] = printThroughStep(a3 / norm, target[o + 3 * nx], a);
    if (j + 4 < ny) target[o + 4 * nx] = printThroughStep(a4 / norm, target[o + 4 * nx], a);
    if (j + 5 < ny) target[o + 5 * nx] = printThroughStep(a5 / norm, target[o + 5 * nx], a);
    if (j + 6 < ny) target[o + 6 * nx] = printThroughStep(a6 / norm, target[o + 6 * nx], a);
    if (j + 7 < ny) target[o + 7 * nx] = printThroughStep(a7 / norm, target[o + 7 * nx], a);
}
