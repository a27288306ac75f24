#version 450
// Tabulated-kernel exposure: adds one depth stencil's gather of a layer's deposit to one voxel
// slice (see include/vpsim/exposure/tabulated_engine.h). out(i, j) += sum w(di, dj) S(i+di, j+dj).
//
// Shaped for lavapipe (Mesa 22.3, 8 lanes; docs/PLATFORM.md), where a texelFetch is a call that
// spills every live vector, a uniform-block load at an index computed in a loop is a per-lane
// gather, and storage loads and stores go lane by lane. Each invocation sums 8 consecutive outputs
// of one row in 8 named accumulators. A stencil row is walked in chunks of 8 taps, two vec4
// uniform loads per chunk at an address the same in every lane (cheaper on lavapipe than one
// lane's load handed to the others by subgroupBroadcast); the deposit window of 16 floats slides
// along the row by two vec4 texel fetches per chunk (an RGBA32F view of the zero-padded deposit,
// aligned to 4 floats, so no fetch needs a bounds check). A stencil row whose deposit rows are
// all zero for the subgroup is skipped (the rowNonEmpty flags): the sum is the same, its terms
// are all zero.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
layout(local_size_x = 8, local_size_y = 8) in;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"
#include "exposure_chunk.glsl"

layout(push_constant) uniform Push { ExposureStencilParams params; };
layout(binding = 0) uniform samplerBuffer deposit;
layout(std140, binding = 1) uniform Weights { vec4 weights[STENCIL_CHUNK_BLOCK * 2]; };
// Per stencil row t = dj + H: (first chunk in Weights, chunk count, di of the first tap, 0).
layout(std140, binding = 2) uniform Rows { ivec4 rows[STENCIL_ROW_BLOCK]; };
layout(std430, binding = 3) buffer Slice { float slice[]; };
layout(std430, binding = 4) readonly buffer RowFlags { uint rowNonEmpty[]; };

void main() {
    const int H = params.halfWidth, pw = int(params.paddedWidth);
    const int i0 = int(gl_GlobalInvocationID.x) * 8, j = int(gl_GlobalInvocationID.y);
    float a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0, a4 = 0.0, a5 = 0.0, a6 = 0.0, a7 = 0.0;
    for (int t = 0; t <= 2 * H; ++t) {
        // Padded deposit row of source row j + t - H.
        const int row = j + params.padding - H + t;
        if (!subgroupAny(rowNonEmpty[row] != 0u)) continue;
        const ivec4 r = rows[t];
        // Texel (4 floats) holding the window's first float, i0 + di of the row's first tap.
        int at = (row * pw + int(params.columnPadding) + i0 + r.z) >> 2;
        vec4 lo = texelFetch(deposit, at), hi = texelFetch(deposit, at + 1);
        for (int c = r.x; c < r.x + r.y; ++c) {
            const vec4 lo2 = texelFetch(deposit, at + 2), hi2 = texelFetch(deposit, at + 3);
            addChunk(weights[2 * c], weights[2 * c + 1], lo, hi, lo2, hi2, a0, a1, a2, a3, a4, a5, a6, a7);
            lo = lo2;
            hi = hi2;
            at += 2;
        }
    }
    const int nx = int(params.nx), ny = int(params.ny);
    if (j >= ny) return;
    const int o = j * nx + i0;
    if (i0 + 0 < nx) slice[o + 0] += a0;
    if (i0 + 1 < nx) slice[o + 1] += a1;
    if (i0 + 2 < nx) slice[o + 2] += a2;
    if (i0 + 3 < nx) slice[o + 3] += a3;
    if (i0 + 4 < nx) slice[o + 4] += a4;
    if (i0 + 5 < nx) slice[o + 5] += a5;
    if (i0 + 6 < nx) slice[o + 6] += a6;
    if (i0 + 7 < nx) slice[o + 7] += a7;
}
