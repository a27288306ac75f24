#version 450
// One Gaussian pass of the fitted-kernel exposure (include/vpsim/exposure/exposure_engine.h),
// specialised by AXIS: along x (0) from the zero-padded deposit into the pass buffer, written
// transposed (column i of the grid is its row i), or along y (1) from that buffer into the running
// sum R. Either way the pass runs along the rows of its source, so both read the same way. The
// print-through recursion is taken on the deposit before the blur (the host uploads the running
// deposit S_k = D_k + a S_(k-1); the blur is linear, so blur(S_k) = B_k + a R_(k-1) = R_k): the y
// pass only stores, where a load of R before each store would cost lavapipe a second lane-by-lane
// loop per cell.
//
// Shaped for lavapipe like exposure_stencil.comp (docs/PLATFORM.md: a texelFetch is a call that
// spills every live vector, a uniform-block load at a computed index is a per-lane gather): each
// invocation sums 8 consecutive outputs along its source row in 8 named accumulators; the taps come
// in chunks of 8, two vec4 uniform loads per chunk at an address the same in every lane; the window
// of 16 source floats slides by two vec4 texel fetches per chunk. Rows are zero-padded by PADDING
// (HALF_WIDTH to a multiple of 4) cells on the left and the taps by zeros from -PADDING, so no
// fetch needs a bounds check and the fetches stay aligned; HALF_WIDTH is a specialisation
// constant, so the chunk loop has a fixed count.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const int HALF_WIDTH = 1;
layout(constant_id = 1) const uint AXIS = 0u;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"
#include "exposure_chunk.glsl"

const int PADDING = (HALF_WIDTH + 3) / 4 * 4;
const int CHUNKS = (HALF_WIDTH + PADDING + STENCIL_CHUNK) / STENCIL_CHUNK;

layout(push_constant) uniform Push { ExposureBlurParams params; };
layout(binding = 0) uniform samplerBuffer source;
// Tap k is the weight of offset k - PADDING (zero beyond HALF_WIDTH).
layout(std140, binding = 1) uniform Taps { vec4 taps[EXPOSURE_TAP_BLOCK / 4]; };
layout(std430, binding = 2) buffer Target { float target[]; };

void main() {
    const bool alongX = AXIS == 0u;
    // Outputs u0 .. u0 + 7 of source row v: x: cells (u0 + r, j = v); y: cells (i = v, u0 + r).
    const int u0 = int(gl_GlobalInvocationID.x) * 8, v = int(gl_GlobalInvocationID.y);
    float a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0, a4 = 0.0, a5 = 0.0, a6 = 0.0, a7 = 0.0;
    // Output u's first tap (offset -PADDING) reads the row's float u: the texel of u0.
    int at = (v * int(params.sourceWidth) + u0) >> 2;
    vec4 lo = texelFetch(source, at), hi = texelFetch(source, at + 1);
    [[unroll]] for (int c = 0; c < CHUNKS; ++c) {
        const vec4 lo2 = texelFetch(source, at + 2), hi2 = texelFetch(source, at + 3);
        addChunk(taps[2 * c], taps[2 * c + 1], lo, hi, lo2, hi2, a0, a1, a2, a3, a4, a5, a6, a7);
        lo = lo2;
        hi = hi2;
        at += 2;
    }
    const float norm = params.norm;
    const int nx = int(params.nx), ny = int(params.ny);
    if (alongX) {
        // Into the pass buffer's row u (grid column u), after its PADDING zero cells.
        if (v >= ny) return;
        const int w = int(params.targetWidth), o = u0 * w + PADDING + v;
        if (u0 + 0 < nx) target[o + 0 * w] = a0 / norm;
        if (u0 + 1 < nx) target[o + 1 * w] = a1 / norm;
        if (u0 + 2 < nx) target[o + 2 * w] = a2 / norm;
        if (u0 + 3 < nx) target[o + 3 * w] = a3 / norm;
        if (u0 + 4 < nx) target[o + 4 * w] = a4 / norm;
        if (u0 + 5 < nx) target[o + 5 * w] = a5 / norm;
        if (u0 + 6 < nx) target[o + 6 * w] = a6 / norm;
        if (u0 + 7 < nx) target[o + 7 * w] = a7 / norm;
        return;
    }
    if (v >= nx) return;
    const int o = u0 * nx + v;
    if (u0 + 0 < ny) target[o + 0 * nx] = a0 / norm;
    if (u0 + 1 < ny) target[o + 1 * nx] = a1 / norm;
    if (u0 + 2 < ny) target[o + 2 * nx] = a2 / norm;
    if (u0 + 3 < ny) target[o + 3 * nx] = a3 / norm;
    if (u0 + 4 < ny) target[o + 4 * nx] = a4 / norm;
    if (u0 + 5 < ny) target[o + 5 * nx] = a5 / norm;
    if (u0 + 6 < ny) target[o + 6 * nx] = a6 / norm;
    if (u0 + 7 < ny) target[o + 7 * nx] = a7 / norm;
}
