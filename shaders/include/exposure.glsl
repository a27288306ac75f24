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
/// over the stencils' common shape, so its code grows with the shape's taps (pipeline creation on
/// lavapipe, when each invocation summed two output rows over all 2H + 1 stencil rows: 0.36 s at
/// 11 cells, 1.07 s at 20, 4.05 s at 32; the folded rows since took 0.18 -> 0.06 s at 12); past
/// this the engine takes the CPU path.
const int STENCIL_MAX_HALF_WIDTH = 32;

/// Taps per chunk of a stencil row in exposure_stencil.comp, and the consecutive outputs of one
/// row each invocation sums (exposure_blur.comp uses the same chunks).
const int STENCIL_CHUNK = 8;
const int STENCIL_OUTPUTS = 16;
/// exposure_stencil.comp's workgroup: invocations along x (each STENCIL_OUTPUTS outputs of a row)
/// and along y (a row each). Lavapipe runs 8 invocations along x as the lanes of one vector: 4
/// x 16 (narrower workgroups, less padding on the grid's right) ran 1.7x slower. 32 outputs per
/// invocation measured 42 against 45 ns/voxel in `bench_exposure engines` but 27 against 26 in
/// `bench_pipeline --engines` (256-column workgroups pad its 1030 columns by a quarter), with
/// twice the code to compile.
const int STENCIL_GROUP_X = 8;
const int STENCIL_GROUP_Y = 8;
/// The most depth stencils one exposure_stencil.comp invocation applies to each folded window it
/// fetches (its slices are bindings 2..5).
const int STENCIL_MAX_PER_INVOCATION = 4;

/// A stencil row whose taps reach |di| <= halfWidth is walked in chunks from this first tap,
/// aligned to 4 cells so the shader's vec4 fetches stay aligned.
int stencilRowFirst(int halfWidth) {
    return halfWidth < 0 ? 0 : -((halfWidth + 3) / 4 * 4);
}

/// Chunks covering taps stencilRowFirst(halfWidth)..halfWidth; none for an empty row (-1).
int stencilRowChunks(int halfWidth) {
    return halfWidth < 0
               ? 0
               : (halfWidth - stencilRowFirst(halfWidth) + STENCIL_CHUNK) / STENCIL_CHUNK;
}

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
