#version 450
// Photon Monte Carlo (seed 000 Section II-B) with persistent invocations: invocation i traces
// photons photonStart + i, + stride, + 2*stride, ... below photonEnd, launching the next photon
// inside the step loop as soon as one ends so that SIMD lanes stay busy. The physics is
// shaders/include/photon_step.glsl (shared with the CPU path). Tallies are integer weight quanta:
// per-invocation sums in registers flushed once with 64-bit atomics, absorption bins with one
// 64-bit atomic per absorbed photon. Float atomics are avoided: they would bias the totals.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

layout(local_size_x = 64) in;
// Entries of the inverse-CDF phase table held in shared memory (1 for Henyey-Greenstein).
layout(constant_id = 0) const uint PHASE_TABLE_CAPACITY = 1u;

#include "glsl_common.glsl"
#include "rng.glsl"
#include "photon_types.glsl"

layout(push_constant) uniform Push { PhotonParams params; } pc;
layout(std430, set = 0, binding = 0) buffer Tallies { uint64_t tally[]; };
layout(std430, set = 0, binding = 1) readonly buffer PhaseTable { float phaseTable[]; };
layout(std430, set = 0, binding = 2) buffer Grid { uint64_t grid[]; };

// The table is read at random once per scattering: shared memory is the cheap place for it
// (DESIGN.md: repeated storage-buffer loads in loops are slow on lavapipe).
shared float sPhaseTable[PHASE_TABLE_CAPACITY];
float photonPhaseTable(int i) { return sPhaseTable[i]; }

#include "photon_step.glsl"

void main() {
    PhotonParams p = pc.params;
    for (uint i = gl_LocalInvocationID.x; i < p.phaseTableSize && i < PHASE_TABLE_CAPACITY; i += 64u)
        sPhaseTable[i] = phaseTable[i];
    barrier();

    uint invocation = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (invocation >= p.invocationStride) return;
    uint specularQuanta = p.launchWeight - p.enteringWeight;
    uint64_t weight = uint64_t(p.enteringWeight);

    uint64_t specular = 0ul, diffuse = 0ul, transmitted = 0ul, absorbed = 0ul, escaped = 0ul;
    uint64_t scatterings = 0ul;
    uint64_t within0 = 0ul, within1 = 0ul, within2 = 0ul, within3 = 0ul;

    uint next = p.photonStart + invocation;
    bool alive = false;
    PhotonState s;
    RngState rng;
    for (;;) {
        if (!alive) {
            if (next >= p.photonEnd) break;
            photonLaunch(p, next, s, rng);
            next += p.invocationStride;
            specular += uint64_t(specularQuanta);
            alive = true;
        }
        int event = photonStep(p, s, rng);
        if (event == PHOTON_EVENT_MOVED) continue;
        if (event == PHOTON_EVENT_SCATTERED) {
            scatterings += 1ul;
            continue;
        }
        alive = false;
        if (event == PHOTON_EVENT_REFLECTED) diffuse += weight;
        else if (event == PHOTON_EVENT_TRANSMITTED) transmitted += weight;
        else if (event == PHOTON_EVENT_ESCAPED) escaped += weight;
        else {
            absorbed += weight;
            if (s.pos.z < p.depth0) within0 += weight;
            if (s.pos.z < p.depth1) within1 += weight;
            if (s.pos.z < p.depth2) within2 += weight;
            if (s.pos.z < p.depth3) within3 += weight;
            int bin = photonRzBin(p, s.pos);
            if (bin >= 0) atomicAdd(tally[PHOTON_BIN_OFFSET + uint(bin)], weight);
            int voxel = photonGridVoxel(p, s.pos);
            if (voxel >= 0) atomicAdd(grid[uint(voxel)], weight);
        }
    }

    // Every photon of this invocation is in the same batch because the stride is a multiple of
    // PHOTON_BATCHES.
    uint base = ((p.photonStart + invocation) % PHOTON_BATCHES) * PHOTON_TALLY_STRIDE;
    atomicAdd(tally[base + PHOTON_TALLY_SPECULAR], specular);
    atomicAdd(tally[base + PHOTON_TALLY_DIFFUSE], diffuse);
    atomicAdd(tally[base + PHOTON_TALLY_TRANSMITTED], transmitted);
    atomicAdd(tally[base + PHOTON_TALLY_ABSORBED], absorbed);
    atomicAdd(tally[base + PHOTON_TALLY_ESCAPED], escaped);
    atomicAdd(tally[base + PHOTON_TALLY_SCATTERINGS], scatterings);
    atomicAdd(tally[base + PHOTON_TALLY_WITHIN + 0u], within0);
    atomicAdd(tally[base + PHOTON_TALLY_WITHIN + 1u], within1);
    atomicAdd(tally[base + PHOTON_TALLY_WITHIN + 2u], within2);
    atomicAdd(tally[base + PHOTON_TALLY_WITHIN + 3u], within3);
}
