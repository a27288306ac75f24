// The inner step of exposure_blur.comp's x pass (GLSL only): 8 taps of a row
// applied to 8 consecutive outputs.
#ifndef VPSIM_EXPOSURE_CHUNK
#define VPSIM_EXPOSURE_CHUNK

#define VPSIM_CHUNK_TAP(w, x0, x1, x2, x3, x4, x5, x6, x7) \
    {                                                      \
        a0 = fma(w, x0, a0);                               \
        a1 = fma(w, x1, a1);                               \
        a2 = fma(w, x2, a2);                               \
        a3 = fma(w, x3, a3);                               \
        a4 = fma(w, x4, a4);                               \
        a5 = fma(w, x5, a5);                               \
        a6 = fma(w, x6, a6);                               \
        a7 = fma(w, x7, a7);                               \
    }

/// Adds taps k = 0..7 of a chunk to outputs r = 0..7: a_r += w_k s_(r + k), where w_0..w_7 are
/// t0, t1 and s_0..s_15 are lo, hi, lo2, hi2. The taps are the same in every lane: on lavapipe
/// a uniform-block load at an address that no lane's data decides costs less than handing one
/// lane's load to the others (subgroupBroadcast, about a third of the tabulated shader's time).
void addChunk(vec4 t0, vec4 t1, vec4 lo, vec4 hi, vec4 lo2, vec4 hi2, inout float a0,
              inout float a1, inout float a2, inout float a3, inout float a4, inout float a5,
              inout float a6, inout float a7) {
    VPSIM_CHUNK_TAP(t0.x, lo.x, lo.y, lo.z, lo.w, hi.x, hi.y, hi.z, hi.w)
    VPSIM_CHUNK_TAP(t0.y, lo.y, lo.z, lo.w, hi.x, hi.y, hi.z, hi.w, lo2.x)
    VPSIM_CHUNK_TAP(t0.z, lo.z, lo.w, hi.x, hi.y, hi.z, hi.w, lo2.x, lo2.y)
    VPSIM_CHUNK_TAP(t0.w, lo.w, hi.x, hi.y, hi.z, hi.w, lo2.x, lo2.y, lo2.z)
    VPSIM_CHUNK_TAP(t1.x, hi.x, hi.y, hi.z, hi.w, lo2.x, lo2.y, lo2.z, lo2.w)
    VPSIM_CHUNK_TAP(t1.y, hi.y, hi.z, hi.w, lo2.x, lo2.y, lo2.z, lo2.w, hi2.x)
    VPSIM_CHUNK_TAP(t1.z, hi.z, hi.w, lo2.x, lo2.y, lo2.z, lo2.w, hi2.x, hi2.y)
    VPSIM_CHUNK_TAP(t1.w, hi.w, lo2.x, lo2.y, lo2.z, lo2.w, hi2.x, hi2.y, hi2.z)
}

/// The same for 4 taps t0 (a chunk's first half) on s_0..s_11 = lo, hi, lo2: a row's last taps when
/// they fill half a chunk or less (exposure_blur.comp).
void addHalfChunk(vec4 t0, vec4 lo, vec4 hi, vec4 lo2, inout float a0, inout float a1,
                  inout float a2, inout float a3, inout float a4, inout float a5, inout float a6,
                  inout float a7) {
    VPSIM_CHUNK_TAP(t0.x, lo.x, lo.y, lo.z, lo.w, hi.x, hi.y, hi.z, hi.w)
    VPSIM_CHUNK_TAP(t0.y, lo.y, lo.z, lo.w, hi.x, hi.y, hi.z, hi.w, lo2.x)
    VPSIM_CHUNK_TAP(t0.z, lo.z, lo.w, hi.x, hi.y, hi.z, hi.w, lo2.x, lo2.y)
    VPSIM_CHUNK_TAP(t0.w, lo.w, hi.x, hi.y, hi.z, hi.w, lo2.x, lo2.y, lo2.z)
}

#endif
