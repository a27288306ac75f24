// The photon Monte Carlo physics, written once for the GPU (shaders/photon_mc.comp) and the CPU
// (src/transport/mc_cpu.cpp through include/vpsim/core/glsl_shim.h). Seed 000 Section II-B:
// photons enter at normal incidence (Gaussian beam Eq. 6 or pencil), travel exponential free
// paths (Eq. 7 and 10 combined: total attenuation mut = mua + mus), and at each interaction are
// absorbed or scattered with an angle drawn from the phase function (Eq. 5, via its inverse CDF,
// or Henyey-Greenstein).
//
// Absorption is ANALOG: at an interaction the whole photon is absorbed with probability mua/mut,
// otherwise it scatters. Every photon therefore ends in exactly one tally with its full weight,
// which makes the integer energy balance exact by construction and needs no Russian roulette
// (which creates and destroys weight); in strongly scattering slurries (albedo ~0.97) it is also
// ~10x cheaper per photon than implicit capture followed down to a small weight cut-off.
// Fresnel reflection at the surfaces is analog too: the photon is reflected whole with
// probability R(theta) (unpolarised Fresnel), else it leaves. The free path after a boundary
// event is drawn afresh, which is exact because the exponential distribution is memoryless.
//
// Requires, before inclusion: glsl_common.glsl, rng.glsl, photon_types.glsl and a function
// `float photonPhaseTable(int i)` returning entry i of the inverse CDF of cos(theta)
// (entries at u = i/(n-1), +1 at u = 0 down to -1 at u = 1).
#ifndef VPSIM_PHOTON_STEP
#define VPSIM_PHOTON_STEP

#ifdef VPSIM_CPU
#define PHOTON_PARAMS_IN const PhotonParams&
#else
#define PHOTON_PARAMS_IN PhotonParams
#endif

const float PHOTON_TWO_PI = 6.283185307179586;
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

// Henyey-Greenstein: cos(theta) from a uniform u in (0,1] (inverse of its CDF).
float photonHgCos(float g, float u) {
    if (g * g < float(1.0e-12)) return float(2) * u - float(1);
    float t = (float(1) - g * g) / (float(1) - g + float(2) * g * u);
    return clamp((float(1) + g * g - t * t) / (float(2) * g), float(-1), float(1));
}

// Tabulated phase function: linear interpolation of the inverse CDF at u.
float photonTableCos(uint n, float u) {
    float x = u * float(n - 1u);
    int i = min(int(x), int(n) - 2);
    float f = x - float(i);
    return mix(photonPhaseTable(i), photonPhaseTable(i + 1), f);
}

// Turns direction d by polar angle theta (cos given) and azimuth phi about itself.
vec3 photonRotate(vec3 d, float cosT, float cosP, float sinP) {
    float sinT = sqrt(max(float(0), float(1) - cosT * cosT));
    vec3 n;
    if (d.z * d.z > float(0.99999)) {
        float s = d.z > float(0) ? float(1) : float(-1);
        n = vec3(sinT * cosP, sinT * sinP, s * cosT);
    } else {
        float t = sqrt(float(1) - d.z * d.z);
        n.x = sinT * (d.x * d.z * cosP - d.y * sinP) / t + d.x * cosT;
        n.y = sinT * (d.y * d.z * cosP + d.x * sinP) / t + d.y * cosT;
        n.z = -sinT * cosP * t + d.z * cosT;
    }
    return normalize(n);  // keeps float round-off from drifting |d| over hundreds of scatterings
}

// Starts photon `index` at the surface heading straight down. Gaussian beam (Eq. 6): intensity
// exp(-2 r^2 / W0^2), W0 the 1/e^2 intensity radius, so r^2 = -W0^2 ln(u) / 2 samples it exactly.
void photonLaunch(PHOTON_PARAMS_IN p, uint index, VPSIM_OUT(PhotonState) s, VPSIM_OUT(RngState) rng) {
    rng = rngSeed(p.seed, index);
    s.pos = vec3(float(0), float(0), float(0));
    s.dir = vec3(float(0), float(0), float(1));
    if (p.beamShape == PHOTON_BEAM_GAUSSIAN) {
        float r = p.beamW0 * sqrt(float(-0.5) * log(rngUniform(rng)));
        float phi = PHOTON_TWO_PI * rngUniform(rng);
        s.pos.x = r * cos(phi);
        s.pos.y = r * sin(phi);
    }
}

// Advances a photon by one free path (or to the boundary it meets first) and returns the
// PHOTON_EVENT_* that ended the step.
int photonStep(PHOTON_PARAMS_IN p, VPSIM_INOUT(PhotonState) s, VPSIM_INOUT(RngState) rng) {
    float mut = p.mua + p.mus;
    float path = mut > float(0) ? -log(rngUniform(rng)) / mut : PHOTON_FAR;
    float toSurface = PHOTON_FAR;
    if (s.dir.z < float(0)) toSurface = -s.pos.z / s.dir.z;
    else if (s.dir.z > float(0) && p.thickness > float(0)) toSurface = (p.thickness - s.pos.z) / s.dir.z;

    if (path >= toSurface) {
        bool top = s.dir.z < float(0);
        s.pos += s.dir * toSurface;
        s.pos.z = top ? float(0) : p.thickness;
        float reflectance = photonFresnel(p.nMedium, top ? p.nAbove : p.nBelow, abs(s.dir.z));
        if (rngUniform(rng) <= reflectance) {
            s.dir.z = -s.dir.z;
            return PHOTON_EVENT_MOVED;
        }
        return top ? PHOTON_EVENT_REFLECTED : PHOTON_EVENT_TRANSMITTED;
    }

    s.pos += s.dir * path;
    if (p.lateralRadius > float(0) && s.pos.x * s.pos.x + s.pos.y * s.pos.y > p.lateralRadius * p.lateralRadius)
        return PHOTON_EVENT_ESCAPED;
    if (rngUniform(rng) * mut <= p.mua) return PHOTON_EVENT_ABSORBED;

    float u = rngUniform(rng);
    float cosT = p.phaseModel == PHOTON_PHASE_TABLE ? photonTableCos(p.phaseTableSize, u) : photonHgCos(p.g, u);
    float phi = PHOTON_TWO_PI * rngUniform(rng);
    s.dir = photonRotate(s.dir, cosT, cos(phi), sin(phi));
    return PHOTON_EVENT_SCATTERED;
}

// Index of the cylindrical tally bin holding pos ([iz * rBins + ir]), or -1 outside the grid.
int photonRzBin(PHOTON_PARAMS_IN p, vec3 pos) {
    float fr = sqrt(pos.x * pos.x + pos.y * pos.y) / p.rBinWidth;
    float fz = pos.z / p.zBinWidth;
    if (!(fr < float(p.rBins)) || !(fz < float(p.zBins)) || fz < float(0)) return -1;
    return int(uint(fz) * p.rBins + uint(fr));
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

#endif
