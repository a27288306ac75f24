#version 450
// Tabulated-kernel exposure: adds STENCILS depth stencils' gathers of a layer's deposit each to
// its voxel slice (see include/vpsim/exposure/tabulated_engine.h).
// out_t(i, j) += sum w_t(di, dj) S(i+di, j+dj).
//
// The stencils are symmetric in dj (the kernel is radial), so stencil row d takes deposit rows
// j + d and j - d added as they are fetched (the CPU gather's folded rows, stencil_gather.h):
// H + 1 rows of multiply-adds per output instead of 2H + 1. Each folded window fetched feeds
// the STENCILS stencils of the host's group (up to STENCIL_MAX_PER_INVOCATION), since the
// fetches cost on lavapipe about what one stencil's multiply-adds do.
//
// Shaped for lavapipe (Mesa 22.3, 8 lanes; docs/PLATFORM.md), where a texelFetch is a call that
// spills every live vector, a load from a uniform block is a per-lane gather even at a constant
// address, a load from shared memory at an address the same in every lane is one scalar load,
// and a branch or a loop whose count the compiler cannot see carries its values through memory.
// So the pipeline is specialised to the stencils' common shape (per stencil row, the widest
// row half-width of any of the engine's stencils) and both loops are unrolled: every tap's
// address is a constant, there is no loop state and no branch (a test per row, or a workgroup
// returning early, kept the whole state under a lane mask). Each invocation sums
// STENCIL_OUTPUTS consecutive outputs of row j, walking each stencil row in chunks of 8 taps,
// the folded window sliding along it by two vec4 texel fetches per deposit row and chunk (an
// RGBA32F view of the zero-padded deposit, aligned to 4 floats, so no fetch needs a bounds
// check). Within a chunk one sum at a time takes its 8 taps, so the weights stay in registers
// and each sum is loaded and stored once per chunk. The group's weights are copied into shared
// memory once per workgroup. The sums are added to the slice as vec4 (a store is a
// lane-by-lane loop per vector, not per float), whose rows and columns are padded to whole
// workgroups, so no store needs a bounds test. The host dispatches only the rectangles of
// workgroups that some deposit reaches (params.groupX, groupY: the first workgroup of the
// dispatch). Before the fold each invocation summed two output rows from each fetched deposit
// row: the fold costs twice the fetches per output and halves the multiply-adds, 18.6-19.3 ->
// 14.9-17.5 ns/voxel in `bench_pipeline --engines`, with a quarter of the code per stencil
// (pipeline creation 0.18 -> 0.06 s at 12 cells each side, one stencil per invocation).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"

layout(local_size_x = STENCIL_GROUP_X, local_size_y = STENCIL_GROUP_Y) in;

// The common shape: its half-width, the chunks of its rows dj = 0..HALF_WIDTH in all, and per
// row d = |dj| the largest |di| of a tap (-1: no tap in that row; rows -d and d are the same).
layout(constant_id = 0) const int HALF_WIDTH = 0;
layout(constant_id = 1) const int CHUNKS = 1;
// Stencils per invocation, 1..STENCIL_MAX_PER_INVOCATION: each folded window fetched feeds all.
layout(constant_id = 35) const int STENCILS = 1;
#define VPSIM_ROW(d) layout(constant_id = 2 + d) const int ROW_##d = -1;
VPSIM_ROW(0) VPSIM_ROW(1) VPSIM_ROW(2) VPSIM_ROW(3) VPSIM_ROW(4) VPSIM_ROW(5) VPSIM_ROW(6)
VPSIM_ROW(7) VPSIM_ROW(8) VPSIM_ROW(9) VPSIM_ROW(10) VPSIM_ROW(11) VPSIM_ROW(12) VPSIM_ROW(13)
VPSIM_ROW(14) VPSIM_ROW(15) VPSIM_ROW(16) VPSIM_ROW(17) VPSIM_ROW(18) VPSIM_ROW(19) VPSIM_ROW(20)
VPSIM_ROW(21) VPSIM_ROW(22) VPSIM_ROW(23) VPSIM_ROW(24) VPSIM_ROW(25) VPSIM_ROW(26) VPSIM_ROW(27)
VPSIM_ROW(28) VPSIM_ROW(29) VPSIM_ROW(30) VPSIM_ROW(31) VPSIM_ROW(32)

// Rows 0..32: half-widths up to STENCIL_MAX_HALF_WIDTH = 32. Once the row loop is unrolled, d is
// a constant and the switch folds away.
#define VPSIM_CASE(d) \
    case d:           \
        return ROW_##d;
int rowHalfWidth(int d) {
    switch (d) {
        VPSIM_CASE(0) VPSIM_CASE(1) VPSIM_CASE(2) VPSIM_CASE(3) VPSIM_CASE(4) VPSIM_CASE(5)
        VPSIM_CASE(6) VPSIM_CASE(7) VPSIM_CASE(8) VPSIM_CASE(9) VPSIM_CASE(10) VPSIM_CASE(11)
        VPSIM_CASE(12) VPSIM_CASE(13) VPSIM_CASE(14) VPSIM_CASE(15) VPSIM_CASE(16) VPSIM_CASE(17)
        VPSIM_CASE(18) VPSIM_CASE(19) VPSIM_CASE(20) VPSIM_CASE(21) VPSIM_CASE(22) VPSIM_CASE(23)
        VPSIM_CASE(24) VPSIM_CASE(25) VPSIM_CASE(26) VPSIM_CASE(27) VPSIM_CASE(28) VPSIM_CASE(29)
        VPSIM_CASE(30) VPSIM_CASE(31) VPSIM_CASE(32)
    }
    return -1;
}

// The most chunks a row of the shape holds (a row of half-width HALF_WIDTH).
const int MAX_ROW_CHUNKS = (2 * ((HALF_WIDTH + 3) / 4 * 4) + STENCIL_CHUNK) / STENCIL_CHUNK;
const int OUT = STENCIL_OUTPUTS;

layout(push_constant) uniform Push { ExposureStencilParams params; };
layout(binding = 0) uniform samplerBuffer deposit;
// The group's stencils on the common shape, one after another, each per row dj = 0..H its taps on
// the row's chunks of 8 from di = stencilRowFirst(hw) (the host's weightsOnShape).
layout(std140, binding = 1) uniform Weights { vec4 weights[2 * CHUNKS * STENCILS]; };
// Rows of params.sliceWidth outputs (whole workgroups), as many rows as the workgroups cover: the
// slices of the group's stencils (bindings past STENCILS are not used).
layout(std430, binding = 2) buffer Slice0 { vec4 slice0[]; };
layout(std430, binding = 3) buffer Slice1 { vec4 slice1[]; };
layout(std430, binding = 4) buffer Slice2 { vec4 slice2[]; };
layout(std430, binding = 5) buffer Slice3 { vec4 slice3[]; };

shared vec4 taps[2 * CHUNKS * STENCILS];

// Adds sum to texel o of stencil t's slice (t a constant once the loops are unrolled).
void addToSlice(int t, int o, vec4 sum) {
    if (t == 0) slice0[o] += sum;
    else if (t == 1) slice1[o] += sum;
    else if (t == 2) slice2[o] += sum;
    else slice3[o] += sum;
}

void main() {
    const uint invocations = uint(STENCIL_GROUP_X * STENCIL_GROUP_Y);
    for (uint k = gl_LocalInvocationIndex; k < uint(2 * CHUNKS * STENCILS); k += invocations)
        taps[k] = weights[k];
    barrier();

    const int pw = int(params.paddedWidth);
    const ivec2 group = ivec2(gl_WorkGroupID.xy) + ivec2(params.groupX, params.groupY);
    const int i0 = (group.x * STENCIL_GROUP_X + int(gl_LocalInvocationID.x)) * OUT;
    const int j = group.y * STENCIL_GROUP_Y + int(gl_LocalInvocationID.y);
    float a[STENCILS][OUT];
    [[unroll]] for (int t = 0; t < STENCILS; ++t)
        [[unroll]] for (int r = 0; r < OUT; ++r) a[t][r] = 0.0;
    int chunk = 0;  // the row's first chunk in a stencil's taps
    // Stencil row d takes the deposit rows j + d and j - d, added as they are fetched (the
    // stencils are symmetric in dj): the CPU gather's folded rows, in its order.
    [[unroll]] for (int d = 0; d <= HALF_WIDTH; ++d) {
        const int hw = rowHalfWidth(d), count = stencilRowChunks(hw);
        // Texels (4 floats) holding the window's first float: i0 + di of the row's first tap in
        // padded deposit rows j + d and j - d.
        const int column = int(params.columnPadding) + i0 + stencilRowFirst(hw);
        const int up = ((j + params.padding + d) * pw + column) >> 2;
        const int down = ((j + params.padding - d) * pw + column) >> 2;
        // s[m]: the folded deposit m cells right of the current chunk's first tap, for output i0.
        float s[OUT + STENCIL_CHUNK];
        if (count > 0) {
            [[unroll]] for (int q = 0; q < OUT / 4; ++q) {
                vec4 v = texelFetch(deposit, up + q);
                if (d > 0) v += texelFetch(deposit, down + q);
                s[4 * q] = v.x;
                s[4 * q + 1] = v.y;
                s[4 * q + 2] = v.z;
                s[4 * q + 3] = v.w;
            }
        }
        // A fixed count, so the loop unrolls before the shape is known; chunks past the row's
        // count fold away once it is.
        [[unroll]] for (int c = 0; c < MAX_ROW_CHUNKS; ++c) {
            if (c < count) {
                vec4 lo = texelFetch(deposit, up + OUT / 4 + 2 * c);
                vec4 hi = texelFetch(deposit, up + OUT / 4 + 2 * c + 1);
                if (d > 0) {
                    lo += texelFetch(deposit, down + OUT / 4 + 2 * c);
                    hi += texelFetch(deposit, down + OUT / 4 + 2 * c + 1);
                }
                s[OUT] = lo.x;
                s[OUT + 1] = lo.y;
                s[OUT + 2] = lo.z;
                s[OUT + 3] = lo.w;
                s[OUT + 4] = hi.x;
                s[OUT + 5] = hi.y;
                s[OUT + 6] = hi.z;
                s[OUT + 7] = hi.w;
                // Per stencil, one sum at a time takes the chunk's taps: the 8 weights stay in
                // registers, the window slides by one load per sum, each sum is loaded and
                // stored once a chunk.
                [[unroll]] for (int t = 0; t < STENCILS; ++t) {
                    const int at = 2 * (t * CHUNKS + chunk + c);
                    const vec4 w0 = taps[at], w1 = taps[at + 1];
                    const float w[STENCIL_CHUNK] =
                        float[](w0.x, w0.y, w0.z, w0.w, w1.x, w1.y, w1.z, w1.w);
                    [[unroll]] for (int r = 0; r < OUT; ++r)
                        [[unroll]] for (int k = 0; k < STENCIL_CHUNK; ++k)
                            a[t][r] = fma(w[k], s[r + k], a[t][r]);
                }
                [[unroll]] for (int r = 0; r < OUT; ++r) s[r] = s[r + STENCIL_CHUNK];
            }
        }
        chunk += count;
    }

    // Whole vec4 (one lane-by-lane loop per 4 outputs) and no bounds test: the slice's rows and
    // columns are padded to whole workgroups.
    const int o = (j * int(params.sliceWidth) + i0) / 4;
    [[unroll]] for (int t = 0; t < STENCILS; ++t)
        [[unroll]] for (int q = 0; q < OUT / 4; ++q)
            addToSlice(t, o + q, vec4(a[t][4 * q], a[t][4 * q + 1], a[t][4 * q + 2],
                                      a[t][4 * q + 3]));
}
