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

#endif
