// Random numbers for Monte Carlo, identical on CPU and GPU (one source, see glsl_shim.h).
//
// Per-stream seeding (one stream per photon): the state of stream k under seed s is derived by a
// 32-bit bijective hash, so for a fixed seed no two streams start from the same state, and results
// do not depend on how photons are spread over threads. The generator is xoshiro128** (Blackman &
// Vigna 2018): 128-bit state, period 2^128 - 1, passes BigCrush; only 32-bit integer operations,
// so GLSL and C++ produce the same bits.
#ifndef VPSIM_RNG_GLSL
#define VPSIM_RNG_GLSL

struct RngState {
    uint s0;
    uint s1;
    uint s2;
    uint s3;
};

/// "lowbias32" integer hash (C. Wellons): a bijection on 32-bit words with good avalanche.
uint rngHash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

uint rngRotl(uint x, int k) { return (x << k) | (x >> (32 - k)); }

/// Next 32 random bits.
uint rngNext(VPSIM_INOUT(RngState) r) {
    uint result = rngRotl(r.s1 * 5u, 7) * 9u;
    uint t = r.s1 << 9;
    r.s2 ^= r.s0;
    r.s3 ^= r.s1;
    r.s1 ^= r.s2;
    r.s0 ^= r.s3;
    r.s2 ^= t;
    r.s3 = rngRotl(r.s3, 11);
    return result;
}

/// State of stream `stream` under `seed`. s0 is a bijection of the stream index for a fixed seed,
/// so distinct streams never share a state.
RngState rngSeed(uint seed, uint stream) {
    uint seedHash = rngHash(seed ^ 0xA511E9B3u);
    RngState r;
    r.s0 = rngHash(rngHash(stream ^ 0x9E3779B9u) + seedHash);
    r.s1 = rngHash(rngHash(stream ^ 0x632BE5ABu) ^ (seedHash + 0x85157AF5u));
    r.s2 = rngHash(rngHash(stream + 0x2545F491u) + (seedHash ^ 0x4F6CDD1Du));
    r.s3 = rngHash(rngHash(stream + 0x6A09E667u) ^ (seedHash + 0xBB67AE85u));
    if ((r.s0 | r.s1 | r.s2 | r.s3) == 0u) r.s0 = 1u;  // the all-zero state is a fixed point
    // Discard a few outputs so that nearby streams decorrelate fully.
    rngNext(r);
    rngNext(r);
    rngNext(r);
    rngNext(r);
    return r;
}

/// Uniform float in (0, 1]: 24 random bits, never 0, so -log(u) is always finite.
/// (m + 1) * 2^-24 is exact in float, so CPU and GPU agree bit for bit (written with float(1):
/// in C++ a 1.0 would make it double arithmetic and two conversions).
float rngUniform(VPSIM_INOUT(RngState) r) {
    return (float(rngNext(r) >> 8) + float(1)) * float(1.0 / 16777216.0);
}

#endif
