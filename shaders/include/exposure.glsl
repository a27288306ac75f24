// Separable exposure: the arithmetic shared by the shaders and the CPU path (glsl_shim.h).
#ifndef VPSIM_EXPOSURE_GLSL
#define VPSIM_EXPOSURE_GLSL

/// The widest fitted blur exposure_blur.comp takes (half-width in cells): it keeps 2 HALF_WIDTH
/// rows of 8 sums per invocation in registers, and its code and its state grow with them (past
/// this, pipeline creation and the sums' spills cost more than the shader saves; the engine
/// takes the CPU path). A 50 um beam on a 3 um grid is within it.
const int EXPOSURE_BLUR_MAX_HALF_WIDTH = 32;

/// Floats in the fitted blur's uniform block of taps (exposure_blur.comp): the widest blur's taps
/// from its padding on, in whole chunks.
const int EXPOSURE_TAP_BLOCK = 128;

/// Rows exposure_blur.comp blurs per iteration of its strip loop (unrolled) where its y pass
/// scatters into open rows: on lavapipe the loop carries its open rows through memory, once per
/// iteration. Where it gathers from a ring of rows, an iteration is the ring's 2 HALF_WIDTH + 1.
const int EXPOSURE_BLUR_STEPS = 8;

/// The widest blur (half-width in cells) whose y pass gathers from a ring of rows: its code grows
/// with the square of the ring (exposure_blur.comp).
const int EXPOSURE_BLUR_GATHER_MAX_HALF_WIDTH = 16;

/// The widest stencil exposure_stencil.comp takes (half-width in cells): its pipeline is unrolled
/// over the stencils' common shape, so its code and its compilation grow with the shape's taps
/// (tabulated_gpu.cpp: MAX_UNROLLED_VEC4S, DIAGONAL_MAX_WINDOW_FLOATS); past this the engine
/// takes the CPU path.
const int STENCIL_MAX_HALF_WIDTH = 32;

/// Taps per chunk of a row in exposure_blur.comp.
const int STENCIL_CHUNK = 8;
/// The consecutive outputs of one row each exposure_stencil.comp invocation sums.
const int STENCIL_OUTPUTS = 16;
/// exposure_stencil.comp's workgroup: STENCIL_GROUP_X invocations along x, which lavapipe runs as
/// the 8 lanes of one vector, and STENCIL_GROUP_Y such vectors. The lanes of a vector take
/// STENCIL_LANE_BLOCKS blocks of STENCIL_OUTPUTS columns in STENCIL_GROUP_X / STENCIL_LANE_BLOCKS
/// consecutive rows: a workgroup covers 64 columns by 16 rows, so a grid's columns are padded
/// less than by 128 by 8 (1030 columns: to 1088, not 1152). `bench_pipeline --engines`, the same
/// build otherwise: 7.4-8.8 ns/voxel with 128 by 8, 6.9-7.2 with 64 by 16, 7.3-7.6 with 32 by 32.
const int STENCIL_GROUP_X = 8;
const int STENCIL_GROUP_Y = 8;
const int STENCIL_LANE_BLOCKS = 4;
const int STENCIL_GROUP_COLUMNS = STENCIL_LANE_BLOCKS * STENCIL_OUTPUTS;
const int STENCIL_GROUP_ROWS = STENCIL_GROUP_X / STENCIL_LANE_BLOCKS * STENCIL_GROUP_Y;
/// The most depth stencils one exposure_stencil.comp invocation applies to each window it fetches
/// (its slices are bindings 2..7). Six, not four: `bench_pipeline --engines` (11 stencils) 6.9-7.6
/// -> 6.2-6.7 ns/voxel, its pipeline creation 1.8 -> 3.1-3.5 s on lavapipe (0.9 s since the
/// DIAGONAL weights' closed-form index, exposure_stencil.comp's diagonalTap).
const int STENCIL_MAX_PER_INVOCATION = 6;

/// Unnormalised weight of the Gaussian tap `offset` cells from the centre; sigmaCells = W/2/pitch
/// (a 1/e^2 radius W is two standard deviations).
float gaussianTap(int offset, float sigmaCells) {
    float t = float(offset) / sigmaCells;
    return exp(-0.5 * t * t);
}

/// Sum of the taps -halfWidth..halfWidth, used to normalise so the blur conserves energy.
float gaussianNorm(int halfWidth, float sigmaCells) {
    float sum = 0.0;
    for (int o = -halfWidth; o <= halfWidth; ++o) sum += gaussianTap(o, sigmaCells);
    return sum;
}

/// Print-through recursion R_k = B_k + a R_{k+1} (seed 000 Eq. 21 in recursive form).
float printThroughStep(float blurred, float runningBelowTop, float decay) {
    return blurred + decay * runningBelowTop;
}

/// Index of the tap (di, dj) in a (2 halfWidth + 1)^2 depth stencil stored row-major (rows dj).
int stencilIndex(int di, int dj, int halfWidth) {
    return (dj + halfWidth) * (2 * halfWidth + 1) + (di + halfWidth);
}

#endif
