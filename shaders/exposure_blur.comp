#version 450
// The fitted-kernel exposure's Gaussian blur (include/vpsim/exposure/exposure_engine.h), both
// passes in one: from the zero-padded running deposit S into the running sum R. The print-through
// recursion is taken on the deposit before the blur (the host uploads S_k = D_k + a S_(k-1); the
// blur is linear, so blur(S_k) = B_k + a R_(k-1) = R_k), so R is only stored.
//
// Each invocation owns 8 consecutive cells of a row (i0 .. i0 + 7) and walks a strip of
// params.stripRows rows down y. At each step it blurs one source row along x at its 8 cells (the
// x pass, a row of P), and the y pass takes that row of P into the output rows it reaches and
// stores the output row that this row completes. So nothing passes through memory between the
// passes: on lavapipe every storage store is a lane-by-lane loop (docs/PLATFORM.md), and two
// passes through a buffer stored every cell twice. The strip's first 2 HALF_WIDTH steps only take
// in the P rows above the strip.
//
// The y pass has two forms, chosen by HALF_WIDTH (GATHER). Up to
// EXPOSURE_BLUR_GATHER_MAX_HALF_WIDTH it keeps the last 2 HALF_WIDTH + 1 rows of P in a ring and
// gathers each output row from it (in the CPU pass's order of taps): the strip loop is unrolled by
// the ring's length so that every slot has a constant address, and each step stores one row of P
// and loads the ring. Wider, it keeps the 2 HALF_WIDTH open output rows as running sums and adds
// each row of P to all of them, the loop unrolled by EXPOSURE_BLUR_STEPS: on lavapipe each open
// value costs a load, a store and a blend with the loop's execution mask per step, so the gather
// takes 11-17% less time over a whole slab (bench_exposure engines at 9 cells each side,
// bench_pipeline --engines at 12), but its code grows with the square of the ring (pipeline
// creation on lavapipe 0.12 s at 12 cells each side, 0.2-0.4 s at 15, 2.3-2.9 s at 32, against
// 0.05-0.2 s for the open rows).
//
// The x pass is shaped for lavapipe like exposure_stencil.comp (a texelFetch is a call that spills
// every live vector, a uniform-block load at a computed index is a per-lane gather): 8 outputs in
// 8 named accumulators, the taps in chunks of 8 (two vec4 uniform loads per chunk at an address the
// same in every lane), the window of 16 source floats sliding by two vec4 texel fetches per chunk.
// Rows are zero-padded by PADDING cells on the left, and the taps by zeros from -PADDING, so no
// fetch needs a bounds check and the fetches stay aligned. HALF_WIDTH is a specialisation
// constant, so every unrolled loop below has a fixed count. The strip's rows (a multiple of the
// strip loop's unrolled steps) are a push constant: as a specialisation constant they made every
// new grid size a new pipeline, which lavapipe compiled for 0.7 s where Mesa's shader cache had
// not got it (the strip loop is not unrolled either way; ns/voxel unchanged).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(local_size_x = 8) in;
layout(constant_id = 0) const int HALF_WIDTH = 1;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"
#include "exposure_chunk.glsl"
#include "float8_io.glsl"

const int PADDING = (HALF_WIDTH + 3) / 4 * 4;
// The taps from offset -PADDING to HALF_WIDTH: whole chunks of 8, then half a chunk where the rest
// fits in 4 (a full chunk otherwise).
const int TAPS = PADDING + HALF_WIDTH + 1;
// (Integer arithmetic only: glslang's specialisation-constant logic made invalid SPIR-V.)
const int HALF_CHUNK = ((TAPS % STENCIL_CHUNK + 3) / 4) % 2;
const int CHUNKS = (TAPS + STENCIL_CHUNK - 1) / STENCIL_CHUNK - HALF_CHUNK;
// The y pass's form: 1 gathers from a ring of P rows (HALF_WIDTH up to
// EXPOSURE_BLUR_GATHER_MAX_HALF_WIDTH), 0 scatters into open rows. Each form's array has one
// slot in the other.
const int GATHER = 1 - HALF_WIDTH / (EXPOSURE_BLUR_GATHER_MAX_HALF_WIDTH + 1);
const int RING = 2 * HALF_WIDTH + 1;
const int RING_SLOTS = GATHER * RING + 1 - GATHER;
const int OPEN_ROWS = 2 * HALF_WIDTH;
const int OPEN_SLOTS = (1 - GATHER) * OPEN_ROWS + GATHER;

layout(push_constant) uniform Push { ExposureBlurParams params; };
layout(binding = 0) uniform samplerBuffer source;
// Tap k is the weight of offset k - PADDING (zero beyond HALF_WIDTH).
layout(std140, binding = 1) uniform Taps { vec4 taps[EXPOSURE_TAP_BLOCK / 4]; };
// R, in rows of params.targetWidth cells (the grid's rows to whole groups): each invocation stores
// its 8 cells as one u64vec4 (float8_io.glsl), one lane-by-lane loop on lavapipe instead of one
// per cell (or two, as vec4: 10% more time over the whole slab).
layout(std430, binding = 2) buffer Target { u64vec4 target[]; };

// The gather's ring: ring[8 q' + r] is P of source row q at cell i0 + r, q' = q % RING.
float ring[8 * RING_SLOTS];
// The scatter's open rows: open[8 m + r] is the sum so far of output row (P row now arriving) -
// HALF_WIDTH + m at cell i0 + r.
float open[8 * OPEN_SLOTS];

float tap(int offset) {
    const int k = offset + PADDING;
    return taps[k >> 2][k & 3];
}

/// The x pass: P of source texel row `at` at the invocation's 8 cells.
void blurAlongX(int at, out float p[8]) {
    float a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0, a4 = 0.0, a5 = 0.0, a6 = 0.0, a7 = 0.0;
    vec4 lo = texelFetch(source, at), hi = texelFetch(source, at + 1);
    [[unroll]] for (int c = 0; c < CHUNKS; ++c) {
        const vec4 lo2 = texelFetch(source, at + 2 + 2 * c);
        const vec4 hi2 = texelFetch(source, at + 3 + 2 * c);
        addChunk(taps[2 * c], taps[2 * c + 1], lo, hi, lo2, hi2, a0, a1, a2, a3, a4, a5, a6, a7);
        lo = lo2;
        hi = hi2;
    }
    if (HALF_CHUNK == 1)
        addHalfChunk(taps[2 * CHUNKS], lo, hi, texelFetch(source, at + 2 + 2 * CHUNKS), a0, a1, a2,
                     a3, a4, a5, a6, a7);
    p = float[8](a0, a1, a2, a3, a4, a5, a6, a7);
}

/// Stores 8 cells of output row `row` of R, scaled by the passes' divisors.
void storeCells(int row, int i0, float o[8]) {
    const float scale = params.scale;
    target[(row * int(params.targetWidth) + i0) >> 3] =
        packFloats8(vec4(o[0], o[1], o[2], o[3]) * scale, vec4(o[4], o[5], o[6], o[7]) * scale);
}

/// Gather form: P of source texel row `at` into ring slot `slot`.
void keepRow(int at, int slot) {
    float p[8];
    blurAlongX(at, p);
    [[unroll]] for (int r = 0; r < 8; ++r) ring[8 * slot + r] = p[r];
}

/// Gather form: output row `row` from ring slots first .. first + 2 HALF_WIDTH (mod RING), the
/// offsets -HALF_WIDTH .. HALF_WIDTH in that order.
void gatherRow(int row, int first, int i0) {
    float o[8] = float[8](0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    [[unroll]] for (int m = 0; m < RING; ++m) {
        const float t = tap(m - HALF_WIDTH);
        const int slot = (first + m) % RING;
        [[unroll]] for (int r = 0; r < 8; ++r) o[r] = fma(t, ring[8 * slot + r], o[r]);
    }
    storeCells(row, i0, o);
}

/// Scatter form, one step: P of source texel row `at` added to the open rows. Stores the row it
/// completes at `row` when `store`.
void scatterRow(int at, bool store, int row, int i0) {
    float p[8];
    blurAlongX(at, p);
    // The row this P row completes (its last tap, offset +HALF_WIDTH), then the others move up a
    // slot with this row's tap added, and the newest open row starts at offset -HALF_WIDTH.
    const float last = tap(HALF_WIDTH);
    if (store) {
        float o[8];
        [[unroll]] for (int r = 0; r < 8; ++r) o[r] = fma(last, p[r], open[r]);
        storeCells(row, i0, o);
    }
    [[unroll]] for (int m = 0; m + 1 < OPEN_ROWS; ++m) {
        const float t = tap(HALF_WIDTH - m - 1);
        [[unroll]] for (int r = 0; r < 8; ++r) open[8 * m + r] = fma(t, p[r], open[8 * m + 8 + r]);
    }
    const float first = tap(-HALF_WIDTH);
    [[unroll]] for (int r = 0; r < 8; ++r) open[8 * (OPEN_ROWS - 1) + r] = first * p[r];
}

void main() {
    const int stripRows = int(params.stripRows);
    const int i0 = int(gl_GlobalInvocationID.x) * 8, j0 = int(gl_WorkGroupID.y) * stripRows;
    const int rowTexels = int(params.sourceWidth) / 4;
    // Source row q holds grid row q - HALF_WIDTH (zero rows above the grid): grid row j0 + s
    // takes source rows j0 + s .. j0 + s + 2 HALF_WIDTH, and the step reading the last of them
    // completes it.
    int at = (j0 * rowTexels) + (i0 >> 2);
    if (GATHER == 1) {
        [[unroll]] for (int q = 0; q < 2 * HALF_WIDTH; ++q) keepRow(at + q * rowTexels, q);
        at += 2 * HALF_WIDTH * rowTexels;
        for (int s = 0; s < stripRows; s += RING) {
            [[unroll]] for (int u = 0; u < RING; ++u) {
                keepRow(at + u * rowTexels, (2 * HALF_WIDTH + u) % RING);
                gatherRow(j0 + s + u, u, i0);
            }
            at += RING * rowTexels;
        }
    } else {
        [[unroll]] for (int m = 0; m < 8 * OPEN_ROWS; ++m) open[m] = 0.0;
        for (int s = 0; s < OPEN_ROWS; ++s) {
            scatterRow(at, false, 0, i0);
            at += rowTexels;
        }
        for (int s = 0; s < stripRows; s += EXPOSURE_BLUR_STEPS) {
            [[unroll]] for (int u = 0; u < EXPOSURE_BLUR_STEPS; ++u)
                scatterRow(at + u * rowTexels, true, j0 + s + u, i0);
            at += EXPOSURE_BLUR_STEPS * rowTexels;
        }
    }
}
