#version 450
// Tabulated-kernel exposure: adds one depth stencil's gather of a layer's deposit to one voxel
// slice (see include/vpsim/exposure/tabulated_engine.h). out(i, j) += sum w(di, dj) S(i+di, j+dj).
//
// Shaped for lavapipe (Mesa 22), which runs 8 lanes at once, loads storage and shared memory
// lane by lane inside loops, keeps arrays indexed in loops in memory and gathers a uniform block
// at offsets that depend on a loop: each invocation sums 8 rows of one column in 8 named
// accumulators over a window of 8 deposit values sliding down the column, so each weight load
// feeds 8 multiply-adds and each fetch 8 more; the deposit is a texel buffer (one vector gather per
// fetch), zero-padded so no fetch needs a bounds check; the weights are a uniform block. Each
// stencil column runs only over its rows with a non-zero weight (a second small uniform block), so
// the circular support is not swept as a square.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"

layout(push_constant) uniform Push { ExposureStencilParams params; };
layout(binding = 0) uniform samplerBuffer deposit;
layout(std140, binding = 1) uniform Weights { vec4 weights[4096]; };
layout(std140, binding = 2) uniform Columns { ivec4 columns[STENCIL_COLUMN_BLOCK / 2]; };
layout(std430, binding = 3) buffer Slice { float slice[]; };

float weight(int di, int dj, int H) {
    int k = stencilIndex(di, dj, H);
    return weights[k >> 2][k & 3];
}

void main() {
    const int H = params.halfWidth, pw = int(params.paddedWidth), P = params.padding;
    const int i = int(gl_GlobalInvocationID.x), j0 = int(gl_GlobalInvocationID.y) * 8;
    float a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0, a4 = 0.0, a5 = 0.0, a6 = 0.0, a7 = 0.0;
    // Column i + di, source rows j0 - H + t + r in d0..d7 (a window sliding down with t): the
    // weight w(di, t - H) is loaded once and adds d_r to output row j0 + r.
    const int first = (j0 + P - H) * pw + i + P;
    for (int di = -H; di <= H; ++di) {
        // Rows first..last of column di (first > last: an empty column).
        const int c = di + H;
        const ivec4 pair = columns[c >> 1];
        const int rowFirst = (c & 1) == 0 ? pair.x : pair.z, rowLast = (c & 1) == 0 ? pair.y : pair.w;
        int at = first + di + rowFirst * pw;
        float d0 = texelFetch(deposit, at).r, d1 = texelFetch(deposit, at + pw).r;
        float d2 = texelFetch(deposit, at + 2 * pw).r, d3 = texelFetch(deposit, at + 3 * pw).r;
        float d4 = texelFetch(deposit, at + 4 * pw).r, d5 = texelFetch(deposit, at + 5 * pw).r;
        float d6 = texelFetch(deposit, at + 6 * pw).r, d7 = texelFetch(deposit, at + 7 * pw).r;
        for (int t = rowFirst; t <= rowLast; ++t) {
            const float w = weight(di, t - H, H);
            a0 += w * d0; a1 += w * d1; a2 += w * d2; a3 += w * d3;
            a4 += w * d4; a5 += w * d5; a6 += w * d6; a7 += w * d7;
            at += pw;
            d0 = d1; d1 = d2; d2 = d3; d3 = d4; d4 = d5; d5 = d6; d6 = d7;
            d7 = texelFetch(deposit, at + 7 * pw).r;
        }
    }
    if (i >= int(params.nx)) return;
    const int nx = int(params.nx), ny = int(params.ny), at = j0 * nx + i;
    if (j0 + 0 < ny) slice[at + 0 * nx] += a0;
    if (j0 + 1 < ny) slice[at + 1 * nx] += a1;
    if (j0 + 2 < ny) slice[at + 2 * nx] += a2;
    if (j0 + 3 < ny) slice[at + 3 * nx] += a3;
    if (j0 + 4 < ny) slice[at + 4 * nx] += a4;
    if (j0 + 5 < ny) slice[at + 5 * nx] += a5;
    if (j0 + 6 < ny) slice[at + 6 * nx] += a6;
    if (j0 + 7 < ny) slice[at + 7 * nx] += a7;
}
