// Separable exposure: the arithmetic shared by the shaders and the CPU path (glsl_shim.h).
#ifndef VPSIM_EXPOSURE_GLSL
#define VPSIM_EXPOSURE_GLSL

/// Floats in the fitted blur's uniform block of taps (exposure_blur.comp): half-widths up to 511.
const int EXPOSURE_TAP_BLOCK = 1024;

/// Stencil rows in exposure_stencil.comp's block of row descriptions: half-widths up to 63.
const int STENCIL_ROW_BLOCK = 128;

/// Taps per chunk of a stencil row in exposure_stencil.comp (one per lane of an 8-wide subgroup),
/// and chunks in its weight block (64 KiB).
const int STENCIL_CHUNK = 8;
const int STENCIL_CHUNK_BLOCK = 2048;

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
