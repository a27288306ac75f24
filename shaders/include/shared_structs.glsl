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

/// Push constants of exposure_blur.comp: one 1D Gaussian pass along x (axis 0) or y (axis 1).
struct ExposureBlurParams {
    uint nx;           ///< grid cells in x
    uint ny;           ///< grid cells in y
    uint axis;         ///< 0: blur along x, 1: along y
    int halfWidth;     ///< taps on each side of the centre
    float sigmaCells;  ///< Gaussian standard deviation in cells
    float norm;        ///< sum of the taps (gaussianNorm)
    uint pad0;
    uint pad1;
};

/// Push constants of exposure_recursion.comp.
struct ExposureRecursionParams {
    uint count;   ///< cells
    float decay;  ///< exp(-h / De)
    uint pad0;
    uint pad1;
};

/// Push constants of exposure_stencil.comp (tabulated kernel: one depth stencil into one slice).
struct ExposureStencilParams {
    uint nx;           ///< grid cells in x
    uint ny;           ///< grid cells in y
    int halfWidth;     ///< stencil half-width in cells (its weights: the bound uniform block)
    uint paddedWidth;  ///< row length of the zero-padded deposit
    int padding;       ///< zero cells before the deposit's first row and column
    uint pad0;
    uint pad1;
    uint pad2;
};

#endif
