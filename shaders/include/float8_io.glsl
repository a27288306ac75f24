// Eight floats stored as one 32-byte u64vec4 (GLSL only; the shader declares
// GL_EXT_shader_explicit_arithmetic_types_int64, so the device needs shaderInt64). On lavapipe
// a storage-buffer store whose address differs by lane is a lane-by-lane loop, one per vector
// stored: a u64vec4 moves 8 floats per loop where a vec4 moves 4, so half the loops (the fitted
// blur's stores of R: 10% of its time over a whole slab). The bits are moved as they are
// (little-endian: lo.x first in memory), nothing is converted. The tabulated shader's slices
// loaded and stored so measured no faster (their arithmetic dominates) and stay vec4.
#ifndef VPSIM_FLOAT8_IO
#define VPSIM_FLOAT8_IO

u64vec4 packFloats8(vec4 lo, vec4 hi) {
    const uvec4 l = floatBitsToUint(lo), h = floatBitsToUint(hi);
    return u64vec4(packUint2x32(l.xy), packUint2x32(l.zw), packUint2x32(h.xy),
                   packUint2x32(h.zw));
}

#endif
