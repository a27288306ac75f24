// Structs passed between C++ and shaders, compiled as both (see glsl_shim.h). Members are 4-byte
// scalars or vec4/uvec4/ivec4 only, so std430 and C++ agree; tests/gpu/test_struct_layout.cpp
// checks every struct listed in shaders/layout_probe.comp against SPIR-V reflection.
#ifndef VPSIM_SHARED_STRUCTS_GLSL
#define VPSIM_SHARED_STRUCTS_GLSL

/// Push constants of rng_stream.comp (the RNG identity test and the RNG benchmark).
struct RngStreamParams {
    uint seed;             ///< generator seed
    uint firstStream;      ///< index of the first stream written
    uint streamCount;      ///< streams (invocations) in this dispatch
    uint valuesPerStream;  ///< outputs per stream
    uint mode;             ///< 0: raw 32-bit words, 1: rngUniform() float bits
    uint pad0;
    uint pad1;
    uint pad2;
};

/// Push constants of exposure_blur.comp: the fitted kernel's Gaussian blur of the zero-padded
/// running deposit into the running sum.
struct ExposureBlurParams {
    uint nx;           ///< grid cells in x
    uint ny;           ///< grid cells in y
    uint sourceWidth;  ///< row length of the zero-padded deposit, a multiple of 4
    uint targetWidth;  ///< row length of R, nx to whole groups of 64 cells
    float scale;       ///< 1 / (normX normY): the two passes' divisors, applied once to R
    uint stripRows;    ///< rows per invocation (a whole number of the y pass's steps)
    uint pad1;
    uint pad2;
};

/// Push constants of exposure_stencil.comp (tabulated kernel: one depth stencil, the bound uniform
/// block, into one slice; the stencils' common shape is the pipeline's specialisation).
struct ExposureStencilParams {
    uint nx;             ///< grid cells in x
    uint ny;             ///< grid cells in y
    int groupX;          ///< workgroup of the dispatch's first group, along x
    uint paddedWidth;    ///< row length of the zero-padded deposit, a multiple of 4
    int padding;         ///< zero rows before the deposit's first row
    uint columnPadding;  ///< zero cells before each row's first cell, a multiple of 4
    int groupY;          ///< workgroup of the dispatch's first group, along y
    uint sliceWidth;     ///< row length of the slice, whole workgroups of outputs
    uint storeMask;      ///< bit t: slice t takes its first sums (written, not added to)
};

#endif
