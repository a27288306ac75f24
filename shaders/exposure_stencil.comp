#version 450
// Tabulated-kernel exposure: adds STENCILS depth stencils' gathers of a layer's deposit each to
// its voxel slice (see include/vpsim/exposure/tabulated_engine.h).
// out_t(i, j) += sum w_t(di, dj) S(i+di, j+dj).
//
// The kernel is radial, so the stencils are 8-fold symmetric (bit for bit: the host builds them
// so): w(di, dj) = w(|di|, |dj|) = w(|dj|, |di|). The cells that share a weight are added before
// the multiplies, once for all the group's stencils: deposit rows j + d and j - d as they are
// fetched (the CPU gather's folded rows, stencil_gather.h), then columns i + x and i - x of a
// folded row, and where DIAGONAL also the folded row x's columns i + d and i - d with row d's
// columns i + x and i - x. Each stencil then takes one multiply-add per weight of the eighth
// x >= d (65 per output at 11 cells each side, against 222 taps of the folded rows and 529 in
// all). DIAGONAL keeps every folded row's window at once; lavapipe's compilation grows steeply
// with them and a GPU has not the registers, so wider shapes and GPUs take the rows one at a
// time (tabulated_gpu.cpp, useDiagonal). Each window fetched feeds the STENCILS stencils of the
// host's group (up to STENCIL_MAX_PER_INVOCATION).
//
// Shaped for lavapipe (Mesa 22.3, 8 lanes; docs/PLATFORM.md), where a texelFetch is a call that
// spills every live vector, a load from a uniform block is a per-lane gather even at a constant
// address, a load from shared memory at an address the same in every lane is one scalar load,
// a storage load or store is a lane-by-lane loop, and a branch or a loop whose count the compiler
// cannot see carries its values through memory. So the pipeline is specialised to the stencils'
// common shape (per stencil row, the widest row half-width of any of the engine's stencils) and
// every loop is unrolled with a fixed count (the iterations past the shape's fold away once its
// constants are known): every tap's address is a constant, there is no loop state and no branch
// (a test per row, or a workgroup returning early, kept the whole state under a lane mask). Each
// invocation sums STENCIL_OUTPUTS consecutive outputs of row j from windows of vec4 texel
// fetches (an RGBA32F view of the zero-padded deposit, aligned to 4 floats, so no fetch needs a
// bounds check). The group's weights are copied into shared memory once per workgroup. The sums
// start from the slices' vec4 texels, loaded first so that their cache misses overlap the
// arithmetic (the loads at the end were a third of the JIT code's samples), or from zero where
// the host has the dispatch write a slice instead of clearing it (params.storeMask). The slices'
// rows and columns are padded to whole workgroups, so no load or store needs a bounds test. The
// host dispatches only the rectangles of workgroups that some deposit reaches (params.groupX,
// groupY: the first workgroup of the dispatch).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"

layout(local_size_x = STENCIL_GROUP_X, local_size_y = STENCIL_GROUP_Y) in;

// The common shape: its half-width, the weights per stencil in whole vec4 (the host's
// weightsOnShape), and per row d = |dj| the largest |di| of a tap (-1: no tap in that row).
layout(constant_id = 0) const int HALF_WIDTH = 0;
layout(constant_id = 1) const int STENCIL_VEC4S = 1;
// Stencils per invocation, 1..STENCIL_MAX_PER_INVOCATION: each window fetched feeds all.
layout(constant_id = 35) const int STENCILS = 1;
// Whether the cells (+-x, +-d) and (+-d, +-x) are added before the multiplies (every folded row's
// window kept at once), or only (+-x, +-d) (one folded row at a time).
layout(constant_id = 36) const bool DIAGONAL = false;
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

const int OUT = STENCIL_OUTPUTS;
// The widest window's reach past the outputs on either side, in whole vec4.
const int MAX_REACH = (HALF_WIDTH + 3) / 4 * 4;
// A window: the outputs and MAX_REACH cells on either side; window[MAX_REACH + r + x] is the cell x
// cells right of output i0 + r.
const int WINDOW = OUT + 2 * MAX_REACH;

layout(push_constant) uniform Push { ExposureStencilParams params; };
layout(binding = 0) uniform samplerBuffer deposit;
// The group's stencils one after another, STENCIL_VEC4S vec4 each: per row d = 0..H of the shape,
// w(x, d) for x = 0..hw(d), or where DIAGONAL for x = d..HALF_WIDTH (diagonalTap; the host's
// weightsOnShape).
layout(std140, binding = 1) uniform Weights { vec4 weights[STENCIL_VEC4S * STENCILS]; };
// Rows of params.sliceWidth outputs (whole workgroups), as many rows as the workgroups cover: the
// slices of the group's stencils (bindings past STENCILS are not used).
layout(std430, binding = 2) buffer Slice0 { vec4 slice0[]; };
layout(std430, binding = 3) buffer Slice1 { vec4 slice1[]; };
layout(std430, binding = 4) buffer Slice2 { vec4 slice2[]; };
layout(std430, binding = 5) buffer Slice3 { vec4 slice3[]; };
layout(std430, binding = 6) buffer Slice4 { vec4 slice4[]; };
layout(std430, binding = 7) buffer Slice5 { vec4 slice5[]; };

shared vec4 taps[STENCIL_VEC4S * STENCILS];

// Weight k of stencil t (k a constant once the loops are unrolled: one scalar load).
float tap(int t, int k) {
    return taps[t * STENCIL_VEC4S + k / 4][k % 4];
}

// Where DIAGONAL, the index of weight (x, d), d <= x <= HALF_WIDTH: rows d of the taps x = d..H,
// whether the shape has them or not. A closed form, not a count of the taps so far: lavapipe's
// compiler carried that count through every unrolled tap (pipeline creation 3.1-3.6 s, not 0.9).
int diagonalTap(int d, int x) {
    return d * (HALF_WIDTH + 1) - d * (d - 1) / 2 + x - d;
}

// Texel o of stencil t's slice (t a constant once the loops are unrolled), or zero where the
// slice takes its first sums (params.storeMask: not cleared, its contents are stale).
vec4 sliceTexel(int t, int o) {
    if ((params.storeMask & (1u << t)) != 0u) return vec4(0.0);
    if (t == 0) return slice0[o];
    if (t == 1) return slice1[o];
    if (t == 2) return slice2[o];
    if (t == 3) return slice3[o];
    if (t == 4) return slice4[o];
    return slice5[o];
}

// Writes texel o of stencil t's slice.
void storeSlice(int t, int o, vec4 value) {
    if (t == 0) slice0[o] = value;
    else if (t == 1) slice1[o] = value;
    else if (t == 2) slice2[o] = value;
    else if (t == 3) slice3[o] = value;
    else if (t == 4) slice4[o] = value;
    else slice5[o] = value;
}

// Texel q of row d's window for the outputs i0.. of row j: deposit rows j + d and j - d added,
// the window starting `reach` cells left of i0 (a multiple of 4).
vec4 foldedTexel(int d, int reach, int q, int i0, int j) {
    const int pw = int(params.paddedWidth);
    const int column = int(params.columnPadding) + i0 - reach;
    vec4 v = texelFetch(deposit, ((j + params.padding + d) * pw + column) / 4 + q);
    if (d > 0) v += texelFetch(deposit, ((j + params.padding - d) * pw + column) / 4 + q);
    return v;
}

void main() {
    const uint invocations = uint(STENCIL_GROUP_X * STENCIL_GROUP_Y);
    for (uint k = gl_LocalInvocationIndex; k < uint(STENCIL_VEC4S * STENCILS); k += invocations)
        taps[k] = weights[k];
    barrier();

    const ivec2 group = ivec2(gl_WorkGroupID.xy) + ivec2(params.groupX, params.groupY);
    // The vector's lanes: STENCIL_LANE_BLOCKS blocks of OUT columns in consecutive rows.
    const int lane = int(gl_LocalInvocationID.x), laneRows = STENCIL_GROUP_X / STENCIL_LANE_BLOCKS;
    const int i0 = (group.x * STENCIL_LANE_BLOCKS + lane % STENCIL_LANE_BLOCKS) * OUT;
    const int j = group.y * STENCIL_GROUP_ROWS + int(gl_LocalInvocationID.y) * laneRows +
                  lane / STENCIL_LANE_BLOCKS;
    // The sums start from the slices' texels, loaded first so that their cache misses overlap
    // the multiply-adds instead of stalling the stores at the end.
    const int o = (j * int(params.sliceWidth) + i0) / 4;
    float a[STENCILS][OUT];
    [[unroll]] for (int t = 0; t < STENCILS; ++t)
        [[unroll]] for (int q = 0; q < OUT / 4; ++q) {
            const vec4 v = sliceTexel(t, o + q);
            a[t][4 * q] = v.x;
            a[t][4 * q + 1] = v.y;
            a[t][4 * q + 2] = v.z;
            a[t][4 * q + 3] = v.w;
        }
    // Arrays stay in main, indexed by constants: passed to a function, lavapipe's compilation of
    // the wide shapes ran out of hand.
    if (DIAGONAL) {
        // rows[d][MAX_REACH + r + x]: folded row d, x cells right of output i0 + r.
        float rows[HALF_WIDTH + 1][WINDOW];
        [[unroll]] for (int d = 0; d <= HALF_WIDTH; ++d) {
            const int hw = rowHalfWidth(d), reach = (hw + 3) / 4 * 4;
            [[unroll]] for (int q = 0; q < WINDOW / 4; ++q) {
                if (hw >= 0 && q < (OUT + 2 * reach) / 4) {
                    const vec4 v = foldedTexel(d, reach, q, i0, j);
                    const int at = MAX_REACH - reach + 4 * q;
                    rows[d][at] = v.x;
                    rows[d][at + 1] = v.y;
                    rows[d][at + 2] = v.z;
                    rows[d][at + 3] = v.w;
                }
            }
        }
        [[unroll]] for (int r = 0; r < OUT; ++r) {
            const int c = MAX_REACH + r;
            [[unroll]] for (int d = 0; d <= HALF_WIDTH; ++d) {
                const int hw = rowHalfWidth(d);
                [[unroll]] for (int x = 0; x <= HALF_WIDTH; ++x) {
                    if (x >= d && x <= hw) {
                        const int k = diagonalTap(d, x);
                        // (+-x, +-d), then (+-d, +-x).
                        float cells = x == 0 ? rows[d][c] : rows[d][c + x] + rows[d][c - x];
                        if (x > d) cells += d == 0 ? rows[x][c] : rows[x][c + d] + rows[x][c - d];
                        [[unroll]] for (int t = 0; t < STENCILS; ++t)
                            a[t][r] = fma(tap(t, k), cells, a[t][r]);
                    }
                }
            }
        }
    } else {
        int k0 = 0;  // row d's first weight
        [[unroll]] for (int d = 0; d <= HALF_WIDTH; ++d) {
            const int hw = rowHalfWidth(d), reach = (hw + 3) / 4 * 4;
            // row[MAX_REACH + r + x]: folded row d, x cells right of output i0 + r.
            float row[WINDOW];
            [[unroll]] for (int q = 0; q < WINDOW / 4; ++q) {
                if (hw >= 0 && q < (OUT + 2 * reach) / 4) {
                    const vec4 v = foldedTexel(d, reach, q, i0, j);
                    const int at = MAX_REACH - reach + 4 * q;
                    row[at] = v.x;
                    row[at + 1] = v.y;
                    row[at + 2] = v.z;
                    row[at + 3] = v.w;
                }
            }
            [[unroll]] for (int r = 0; r < OUT; ++r) {
                const int c = MAX_REACH + r;
                [[unroll]] for (int x = 0; x <= HALF_WIDTH; ++x) {
                    if (x <= hw) {  // (+-x, +-d)
                        const float cells = x == 0 ? row[c] : row[c + x] + row[c - x];
                        [[unroll]] for (int t = 0; t < STENCILS; ++t)
                            a[t][r] = fma(tap(t, k0 + x), cells, a[t][r]);
                    }
                }
            }
            k0 += hw + 1;
        }
    }

    // Whole vec4 (one lane-by-lane loop per 4 outputs) and no bounds test: the slice's rows and
    // columns are padded to whole workgroups.
    [[unroll]] for (int t = 0; t < STENCILS; ++t)
        [[unroll]] for (int q = 0; q < OUT / 4; ++q)
            storeSlice(t, o + q, vec4(a[t][4 * q], a[t][4 * q + 1], a[t][4 * q + 2],
                                      a[t][4 * q + 3]));
}
