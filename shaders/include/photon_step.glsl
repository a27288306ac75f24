// The photon Monte Carlo physics, written once for the GPU (shaders/photon_mc.comp) and the CPU
// (src/transport/mc_cpu.cpp through include/vpsim/core/glsl_shim.h). Seed 000 Section II-B:
// photons enter at normal incidence (Gaussian beam Eq. 6 or pencil), travel exponential free
// paths (Eq. 7 and 10 combined: total attenuation mut = mua + mus), and at each interaction are
// absorbed or scattered with an angle drawn from the phase function (Eq. 5, via its inverse CDF,
// or Henyey-Greenstein).
//
// Weight is an integer number of quanta, so every tally is an exact integer sum.
// - ANALOG: at an interaction the whole photon is absorbed with probability mua/mut, otherwise it
//   scatters; it ends, whole, in exactly one tally.
// - IMPLICIT and TRACK (implicit capture, as MCML): at every interaction the photon deposits
//   floor(w mua/mut + u) quanta (u uniform in [0,1): unbiased stochastic rounding) and scatters.
//   Below PhotonParams.rouletteWeight it plays Russian roulette: it survives with probability
//   1/PHOTON_ROULETTE_GAIN carrying PHOTON_ROULETTE_GAIN times its weight, else it ends. The
//   weight roulette creates and destroys is tallied too, so
//     launched + rouletteGain = specular + diffuse + transmitted + absorbed + escaped + rouletteLoss
//   holds exactly in integers, and gain - loss is zero in expectation (tested).
//   TRACK tallies the (r,z) bins with the track-length estimator: every flight of weight w adds
//   w mua l to each bin it crosses over a length l (mua times the weighted track length is the
//   expected absorption there); the totals and the depth tallies stay the exact deposits.
// Fresnel reflection at the surfaces is analog: the photon is reflected whole with probability
// R(theta) (unpolarised Fresnel), else it leaves. The free path after a boundary event is drawn
// afresh, which is exact because the exponential distribution is memoryless.
//
// The scattering sampling is in photon_sampling.glsl and the track-length flight tally in
// photon_track.glsl (both included below).
// Requires, before inclusion: glsl_common.glsl, rng.glsl, photon_types.glsl (and on the GPU the
// 64-bit integer extension), and the functions
//   float photonPhaseTable(int i)   entry i of the inverse CDF of cos(theta) (entries at
//                                    u = i/(n-1), +1 at u = 0 down to -1 at u = 1),
//   void photonAddBin(uint batch, uint bin, uint64_t quanta)     adds to (r,z) bin iz*rBins+ir,
//   void photonAddVoxel(uint voxel, uint64_t quanta)             adds to a Cartesian voxel,
//   uint photonEstimator(PhotonParams p)   the PHOTON_ESTIMATOR_* in use (the GPU returns a
//                                          specialisation constant, so unused branches compile out).
#ifndef VPSIM_PHOTON_STEP
#define VPSIM_PHOTON_STEP

#ifdef VPSIM_CPU
#define PHOTON_PARAMS_IN const PhotonParams&
#define PHOTON_DERIVED_IN const PhotonDerived&
#else
#define PHOTON_PARAMS_IN PhotonParams
#define PHOTON_DERIVED_IN PhotonDerived
#endif

const float PHOTON_FAR = 1.0e30;  // "no boundary in this direction", mm

// Unpolarised Fresnel reflectance for light in index n1 hitting n2 with incidence cosine cosI
// (average of the s and p reflectances; 1 beyond the critical angle).
float photonFresnel(float n1, float n2, float cosI) {
    if (n1 == n2) return float(0);
    float sinT2 = (n1 / n2) * (n1 / n2) * max(float(0), float(1) - cosI * cosI);
    if (sinT2 >= float(1)) return float(1);
    float cosT = sqrt(float(1) - sinT2);
    float rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    float rp = (n1 * cosT - n2 * cosI) / (n1 * cosT + n2 * cosI);
    return float(0.5) * (rs * rs + rp * rp);
}

// e^x for x <= 0 (0 below -87) without libm: x = n ln 2 + y, n an integer, |y| <= ln(2)/2, with
// ln 2 in two parts so that y keeps float precision at any n (Cody and Waite); 2^n from the
// exponent bits, e^y by its Taylor series to degree 7: relative error a few 1e-8. n = -int(1/2 -
// x log2(e)) rounds by truncation (floor is a libm call or a long sequence on the CPU path's x86-64
// baseline).
float photonExp(float x) {
    if (x < float(-87)) return float(0);
    int n = -int(float(0.5) - x * float(1.4426950408889634));
    float y = (x - float(n) * float(0.693145751953125)) - float(n) * float(1.4286068203094172e-6);
    float y2 = y * y;
    float p = (float(1) + y) + y2 * ((float(0.5) + y * float(1.0 / 6.0)) +
                                     y2 * ((float(1.0 / 24.0) + y * float(1.0 / 120.0)) +
                                           y2 * (float(1.0 / 720.0) + y * float(1.0 / 5040.0))));
    return uintBitsToFloat(uint(n + 127) << 23) * p;
}

// Constants derived from PhotonParams once per photon (outside the step loop), so that the step
// multiplies where it would otherwise divide (divisions and square roots bound its latency).
struct PhotonDerived {
    float invMut;        // 1 / (mua + mus), mm; 0 when nothing interacts
    float absorbShare;   // mua / mut
    float invRBinWidth;  // 1 / the (r,z) bin sizes
    float invZBinWidth;
    float rBins;         // the (r,z) bin counts as floats
    float zBins;
    float hgOneMinusG2;  // Henyey-Greenstein: 1 - g^2, 1 - g, 2 g, 1 + g^2, 1 / (2 g)
    float hgOneMinusG;
    float hgTwoG;
    float hgOnePlusG2;
    float hgInvTwoG;     // 0 when g is 0 (isotropic)
    float controlKappa;              // control variates (photon_control.glsl): kappa,
    float controlKappaPath;          // kappa / mut,
    float controlDepthFactorBottom;  // exp(-kappa thickness)
};

PhotonDerived photonDerive(PHOTON_PARAMS_IN p) {
    PhotonDerived k;
    float mut = p.mua + p.mus;
    k.invMut = mut > float(0) ? float(1) / mut : float(0);
    k.absorbShare = p.mua * k.invMut;
    k.invRBinWidth = float(1) / p.rBinWidth;
    k.invZBinWidth = float(1) / p.zBinWidth;
    k.rBins = float(p.rBins);
    k.zBins = float(p.zBins);
    k.hgOneMinusG2 = float(1) - p.g * p.g;
    k.hgOneMinusG = float(1) - p.g;
    k.hgTwoG = float(2) * p.g;
    k.hgOnePlusG2 = float(1) + p.g * p.g;
    k.hgInvTwoG = p.g * p.g < float(1.0e-12) ? float(0) : float(0.5) / p.g;
    float diffusion = sqrt(float(3) * p.mua * (p.mua + p.mus * (float(1) - p.g)));
    k.controlKappa = clamp(diffusion, float(0.01) * mut, float(0.5) * mut);
    k.controlKappaPath = k.controlKappa * k.invMut;
    k.controlDepthFactorBottom = photonExp(-k.controlKappa * p.thickness);
    return k;
}

#include "photon_sampling.glsl"

// Random stream of photon index hi * 2^32 + lo: below 2^32 the stream rngSeed(seed, lo), above
// it a stream of a hashed seed (so budgets above 2^32 photons never reuse a stream).
RngState photonStream(uint seed, uint lo, uint hi) {
    return rngSeed(hi == 0u ? seed : rngHash(seed ^ rngHash(hi + 0x3C6EF372u)), lo);
}

// Starts photon index hi * 2^32 + lo at the surface heading straight down, carrying the
// entering weight. Gaussian beam (Eq. 6): intensity exp(-2 r^2 / W0^2), W0 the 1/e^2 intensity
// radius, so r^2 = -W0^2 ln(u) / 2 samples it exactly.
void photonLaunch(PHOTON_PARAMS_IN p, uint lo, uint hi, VPSIM_OUT(PhotonState) s, VPSIM_OUT(RngState) rng) {
    rng = photonStream(p.seed, lo, hi);
    s.pos = vec3(float(0), float(0), float(0));
    s.dir = vec3(float(0), float(0), float(1));
    s.weight = p.enteringWeight;
    s.pendingBin = -1;
    s.pending = float(0);
    s.above = vec4(float(0), float(0), float(0), float(0));
    s.depthFactor = float(1);
    if (p.beamShape == PHOTON_BEAM_GAUSSIAN) {
        float r = p.beamW0 * sqrt(float(0.5) * photonExponential(rngNext(rng)));
        vec2 azimuth = photonAzimuth(rngNext(rng));
        s.pos.x = r * azimuth.x;
        s.pos.y = r * azimuth.y;
    }
}

// Index of the Cartesian voxel holding pos ([(iz * nxy + iy) * nxy + ix]), or -1 outside it.
int photonGridVoxel(PHOTON_PARAMS_IN p, vec3 pos) {
    if (p.gridNxy == 0u) return -1;
    float centre = float(p.gridNxy) * float(0.5);
    float fx = pos.x / p.gridVoxel + centre;
    float fy = pos.y / p.gridVoxel + centre;
    float fz = pos.z / p.gridVoxel;
    float n = float(p.gridNxy);
    if (!(fx >= float(0) && fx < n && fy >= float(0) && fy < n && fz >= float(0) && fz < float(p.gridNz)))
        return -1;
    uint ix = min(uint(fx), p.gridNxy - 1u);
    uint iy = min(uint(fy), p.gridNxy - 1u);
    uint iz = min(uint(fz), p.gridNz - 1u);
    return int((iz * p.gridNxy + iy) * p.gridNxy + ix);
}

// Tallies of one invocation (or one CPU photon), in quanta; scatterings/interactions are counts.
struct PhotonTally {
    uint64_t specular;
    uint64_t diffuse;
    uint64_t transmitted;
    uint64_t absorbed;
    uint64_t escaped;
    uint64_t scatterings;
    uint64_t interactions;
    uint64_t rouletteGain;
    uint64_t rouletteLoss;
    uint64_t within0;
    uint64_t within1;
    uint64_t within2;
    uint64_t within3;
    uint64_t controls[PHOTON_CONTROL_TERMS];  // photon_control.glsl, units of 2^-32
    uint work;  // photon steps + bin crossings of this invocation (GPU budget), not a tally
};

void photonTallyClear(VPSIM_OUT(PhotonTally) t) {
    t.specular = 0ul; t.diffuse = 0ul; t.transmitted = 0ul; t.absorbed = 0ul; t.escaped = 0ul;
    t.scatterings = 0ul; t.interactions = 0ul; t.rouletteGain = 0ul; t.rouletteLoss = 0ul;
    t.within0 = 0ul; t.within1 = 0ul; t.within2 = 0ul; t.within3 = 0ul;
    for (uint i = 0u; i < PHOTON_CONTROL_TERMS; ++i) t.controls[i] = 0ul;
    t.work = 0u;
}

// Index of the cylindrical tally bin holding pos ([iz * rBins + ir]), or -1 outside the grid.
int photonRzBin(PHOTON_PARAMS_IN p, PHOTON_DERIVED_IN k, vec3 pos) {
    float fr = sqrt(pos.x * pos.x + pos.y * pos.y) * k.invRBinWidth;
    float fz = pos.z * k.invZBinWidth;
    if (!(fr < k.rBins) || !(fz < k.zBins) || fz < float(0)) return -1;
    return int(uint(fz) * p.rBins + uint(fr));
}

// Track-length estimator: adds `amount` quanta to `bin` through a one-bin buffer, so that a photon
// lingering in one bin costs one tally write, not one per flight. Flushing writes whole quanta and
// carries the fraction (< 1 quantum) on to the photon's next bin, so nothing is lost but at most
// one quantum per photon at its end. bin -1 (outside the grid) flushes and adds nothing.
void photonPend(VPSIM_INOUT(PhotonState) s, uint batch, int bin, float amount) {
    if (bin != s.pendingBin && s.pendingBin >= 0) {
        float q = floor(s.pending);
        if (q > float(0)) photonAddBin(batch, uint(s.pendingBin), uint64_t(q));
        s.pending -= q;
    }
    s.pendingBin = bin;
    if (bin >= 0) s.pending += amount;
}

#include "photon_track.glsl"
#include "photon_control.glsl"

// Whether the (r,z) bins are track-length estimates.
bool photonTracks(PHOTON_PARAMS_IN p) {
    uint e = photonEstimator(p);
    return e == PHOTON_ESTIMATOR_TRACK || e == PHOTON_ESTIMATOR_IMPLICIT_TRACK;
}

// Whether the (r,z) bins are estimates (track-length or collision), not the deposits themselves.
bool photonBinsEstimated(PHOTON_PARAMS_IN p) {
    return photonTracks(p) || photonEstimator(p) == PHOTON_ESTIMATOR_COLLISION;
}

// Whether the depth tallies are track-length estimates (implicit capture only: with analog
// transport the 0/1 absorption point has less variance over thick layers than mua x path
// length, whose spread is that of an exponential; bench_photon_mc measured 0.14-0.44x).
bool photonTracksDepths(PHOTON_PARAMS_IN p) {
    return photonEstimator(p) == PHOTON_ESTIMATOR_IMPLICIT_TRACK;
}

// Flushes the track-length buffers at the end of a photon (carried fractions are dropped).
void photonFlush(PHOTON_PARAMS_IN p, VPSIM_INOUT(PhotonState) s, uint batch, VPSIM_INOUT(PhotonTally) t) {
    if (!photonTracks(p)) return;  // only the track-length tallies buffer (collision counts do not)
    photonPend(s, batch, -1, float(0));
    if (!photonTracksDepths(p)) return;
    t.within0 += uint64_t(floor(s.above.x + float(0.5)));
    t.within1 += uint64_t(floor(s.above.y + float(0.5)));
    t.within2 += uint64_t(floor(s.above.z + float(0.5)));
    t.within3 += uint64_t(floor(s.above.w + float(0.5)));
}

// Length of the flight z0 -> z1 (of length len) that lies above depth d.
float photonLengthAbove(float z0, float z1, float len, float d) {
    float lo = min(z0, z1), hi = max(z0, z1);
    if (hi <= d) return len;
    if (lo >= d) return float(0);
    return len * (d - lo) / (hi - lo);
}

// Track-length depth tallies: weight x mua x (flight length above each depth), kept per photon
// in float and added as whole quanta when it ends (rounding: < 1 quantum per photon and depth).
void photonTrackDepths(PHOTON_PARAMS_IN p, VPSIM_INOUT(PhotonState) s, float z0, float len) {
    float scale = float(s.weight) * p.mua;
    s.above.x += scale * photonLengthAbove(z0, s.pos.z, len, p.depth0);
    s.above.y += scale * photonLengthAbove(z0, s.pos.z, len, p.depth1);
    s.above.z += scale * photonLengthAbove(z0, s.pos.z, len, p.depth2);
    s.above.w += scale * photonLengthAbove(z0, s.pos.z, len, p.depth3);
}

// Deposits q quanta at the photon's position: the absorbed total, the depth tallies, the
// Cartesian grid and (except for the estimated bins) the (r,z) bins.
void photonDeposit(PHOTON_PARAMS_IN p, PHOTON_DERIVED_IN k, vec3 pos, uint q, uint batch,
                   VPSIM_INOUT(PhotonTally) t) {
    uint64_t w = uint64_t(q);
    t.absorbed += w;
    if (!photonTracksDepths(p)) {
        if (pos.z < p.depth0) t.within0 += w;
        if (pos.z < p.depth1) t.within1 += w;
        if (pos.z < p.depth2) t.within2 += w;
        if (pos.z < p.depth3) t.within3 += w;
    }
    if (!photonBinsEstimated(p)) {
        int bin = photonRzBin(p, k, pos);
        if (bin >= 0) photonAddBin(batch, uint(bin), w);
    }
    int voxel = photonGridVoxel(p, pos);
    if (voxel >= 0) photonAddVoxel(uint(voxel), w);
}

// Advances a photon by one free path (or to the boundary it meets first), tallies what happened
// and returns whether the photon is still alive.
bool photonAdvance(PHOTON_PARAMS_IN p, PHOTON_DERIVED_IN k, VPSIM_INOUT(PhotonState) s, VPSIM_INOUT(RngState) rng,
                   uint batch, VPSIM_INOUT(PhotonTally) t) {
    uint estimator = photonEstimator(p);
    float mut = p.mua + p.mus;
    float path = mut > float(0) ? photonExponential(rngNext(rng)) * k.invMut : PHOTON_FAR;
    // Whether the free path reaches a surface, from the depth it would end at (the division for
    // the distance to the surface only when it does).
    float zEnd = s.pos.z + path * s.dir.z;
    bool slab = p.thickness > float(0);
    bool boundary = !(path < PHOTON_FAR) || (s.dir.z < float(0) && zEnd <= float(0)) ||
                    (s.dir.z > float(0) && slab && zEnd >= p.thickness);
    vec3 start = s.pos;
    float flight = path;
    if (boundary) {
        flight = PHOTON_FAR;
        if (s.dir.z < float(0)) flight = -s.pos.z / s.dir.z;
        else if (s.dir.z > float(0) && slab) flight = (p.thickness - s.pos.z) / s.dir.z;
    }
    s.pos += s.dir * flight;
    bool controls = photonControls(p, k);
    if (controls) photonControlFlight(p, k, s, start.z, boundary, t);
    t.work += 1u;
    if (photonTracks(p)) {
        t.work += photonTrackBins(p, k, s, start, flight, batch);
        if (photonTracksDepths(p)) photonTrackDepths(p, s, start.z, flight);
    }

    if (boundary) {
        bool top = s.dir.z < float(0);
        s.pos.z = top ? float(0) : p.thickness;
        float reflectance = photonFresnel(p.nMedium, top ? p.nAbove : p.nBelow, abs(s.dir.z));
        bool reflected = rngUniform(rng) <= reflectance;
        if (controls) photonControlSurface(k, s, top, reflected, reflectance, t);
        if (reflected) {
            s.dir.z = -s.dir.z;
            return true;
        }
        if (top) t.diffuse += uint64_t(s.weight);
        else t.transmitted += uint64_t(s.weight);
        photonFlush(p, s, batch, t);
        return false;
    }

    t.interactions += 1ul;
    if (p.lateralRadius > float(0) && s.pos.x * s.pos.x + s.pos.y * s.pos.y > p.lateralRadius * p.lateralRadius) {
        t.escaped += uint64_t(s.weight);
        photonFlush(p, s, batch, t);
        return false;
    }
    bool analog = estimator == PHOTON_ESTIMATOR_ANALOG || estimator == PHOTON_ESTIMATOR_TRACK ||
                  estimator == PHOTON_ESTIMATOR_COLLISION;
    if (analog) {
        if (estimator == PHOTON_ESTIMATOR_COLLISION) {  // counts (photon_types.glsl)
            int bin = photonRzBin(p, k, s.pos);
            if (bin >= 0) photonAddBin(batch, uint(bin), 1ul);
        }
        bool absorbed = rngUniform(rng) * mut <= p.mua;
        if (controls) photonControlAbsorption(k, s, absorbed, t);
        if (absorbed) {
            photonDeposit(p, k, s.pos, s.weight, batch, t);
            photonFlush(p, s, batch, t);
            return false;
        }
    } else {
        // Stochastic rounding keeps the deposit unbiased at any weight; w * mua/mut is exact
        // enough in float because w < 2^25.
        float share = floor(float(s.weight) * k.absorbShare + (float(1) - rngUniform(rng)));
        uint q = min(uint(share), s.weight);
        if (q > 0u) photonDeposit(p, k, s.pos, q, batch, t);
        s.weight -= q;
    }

    float u = rngUniform(rng);
    float cosT = p.phaseModel == PHOTON_PHASE_TABLE ? photonTableCos(p.phaseTableSize, u) : photonHgCos(k, u);
    vec2 azimuth = photonAzimuth(rngNext(rng));
    float uzBefore = s.dir.z;
    s.dir = photonRotate(s.dir, cosT, azimuth.x, azimuth.y);
    if (controls) photonControlScatter(p, s, uzBefore, t);
    t.scatterings += 1ul;

    if (!analog && s.weight < p.rouletteWeight) {
        if (s.weight > 0u && rngUniform(rng) * float(PHOTON_ROULETTE_GAIN) <= float(1)) {
            t.rouletteGain += uint64_t(s.weight) * uint64_t(PHOTON_ROULETTE_GAIN - 1u);
            s.weight *= PHOTON_ROULETTE_GAIN;
        } else {
            t.rouletteLoss += uint64_t(s.weight);
            photonFlush(p, s, batch, t);
            return false;
        }
    }
    return true;
}


#endif
