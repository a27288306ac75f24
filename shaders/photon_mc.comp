#version 450
// Photon Monte Carlo (seed 000 Section II-B) with persistent invocations: invocation i traces
// photons photonStart + i, + stride, + 2*stride, ... below photonEnd, launching the next photon
// inside the step loop as soon as one ends so that SIMD lanes stay busy. The physics is
// shaders/include/photon_step.glsl (shared with the CPU path). Tallies are integer weight quanta:
// per-invocation sums in registers flushed once with 64-bit atomics, absorption bins with one
// 64-bit atomic per deposit (per absorbed photon for the analog estimator, per interaction for
// implicit capture, per bin change for the track-length estimator). Float atomics are avoided:
// they would bias the totals.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

layout(local_size_x = 64) in;
// Entries of the inverse-CDF phase table held in shared memory (1 for Henyey-Greenstein).
layout(constant_id = 0) const uint PHASE_TABLE_CAPACITY = 1u;
// The estimator (PhotonParams.estimator & 255) as a constant: lavapipe compiles the step loop
// for 8 lanes at once, and the branches of the other estimators cost it even when not taken.
layout(constant_id = 1) const uint PHOTON_ESTIMATOR_CONSTANT = 0u;

#include "glsl_common.glsl"
#include "rng.glsl"
#include "photon_types.glsl"

layout(push_constant) uniform Push { PhotonParams params; } pc;
layout(std430, set = 0, binding = 0) buffer Tallies { uint64_t tally[]; };
layout(std430, set = 0, binding = 1) readonly buffer PhaseTable { float phaseTable[]; };
layout(std430, set = 0, binding = 2) buffer Grid { uint64_t grid[]; };
layout(std430, set = 0, binding = 3) buffer Resume { uint resume[]; };

// The table is read at random once per scattering: shared memory is the cheap place for it
// (docs/PLATFORM.md: repeated storage-buffer loads in loops are slow on lavapipe).
shared float sPhaseTable[PHASE_TABLE_CAPACITY];
float photonPhaseTable(int i) { return sPhaseTable[i]; }

uint gBinBase = 0u;  // per-batch bins: offset of this invocation's batch
void photonAddBin(uint batch, uint bin, uint64_t quanta) {
    atomicAdd(tally[PHOTON_BIN_OFFSET + gBinBase + bin], quanta);
}
void photonAddVoxel(uint voxel, uint64_t quanta) { atomicAdd(grid[voxel], quanta); }
uint photonEstimator(PhotonParams p) { return PHOTON_ESTIMATOR_CONSTANT; }

#include "photon_step.glsl"

void main() {
    PhotonParams p = pc.params;
    PhotonDerived k = photonDerive(p);
    for (uint i = gl_LocalInvocationID.x; i < p.phaseTableSize && i < PHASE_TABLE_CAPACITY; i += 64u)
        sPhaseTable[i] = phaseTable[i];
    barrier();

    uint invocation = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (invocation >= p.invocationStride) return;
    // Every photon of this invocation is in the same batch because the stride is a multiple of
    // PHOTON_BATCHES (and 2^32 is too, so the low word of the index decides).
    uint batch = (p.photonStart + invocation) % PHOTON_BATCHES;
    if ((p.estimator & PHOTON_FLAG_BATCH_BINS) != 0u) gBinBase = batch * p.rBins * p.zBins;
    uint specularQuanta = p.launchWeight - p.enteringWeight;

    PhotonTally t;
    photonTallyClear(t);
    uint next = invocation;
    bool alive = false;
    PhotonState s;
    RngState rng;
    const uint slot = PHOTON_RESUME_HEADER + invocation * PHOTON_RESUME_SLOT;
    if ((p.estimator & PHOTON_FLAG_RESUME) != 0u) {
        next = resume[slot];
        if (next == PHOTON_RESUME_DONE) return;
        alive = resume[slot + 1u] != 0u;
        s.pos = vec3(uintBitsToFloat(resume[slot + 2u]), uintBitsToFloat(resume[slot + 3u]),
                     uintBitsToFloat(resume[slot + 4u]));
        s.dir = vec3(uintBitsToFloat(resume[slot + 5u]), uintBitsToFloat(resume[slot + 6u]),
                     uintBitsToFloat(resume[slot + 7u]));
        s.weight = resume[slot + 8u];
        s.pendingBin = int(resume[slot + 9u]);
        s.pending = uintBitsToFloat(resume[slot + 10u]);
        rng.s0 = resume[slot + 11u];
        rng.s1 = resume[slot + 12u];
        rng.s2 = resume[slot + 13u];
        rng.s3 = resume[slot + 14u];
        s.above = vec4(uintBitsToFloat(resume[slot + 15u]), uintBitsToFloat(resume[slot + 16u]),
                       uintBitsToFloat(resume[slot + 17u]), uintBitsToFloat(resume[slot + 18u]));
        s.depthFactor = photonExp(-k.controlKappa * s.pos.z);  // as the step left it
    }
    bool suspended = false;
    for (;;) {
        if (!alive) {
            if (next >= p.photonCount) break;
            uint lo = p.photonStart + next;
            photonLaunch(p, lo, p.photonStartHi + (lo < p.photonStart ? 1u : 0u), s, rng);
            next += p.invocationStride;
            t.specular += uint64_t(specularQuanta);
        }
        alive = photonAdvance(p, k, s, rng, batch, t);
        if (t.work >= PHOTON_WORK_BUDGET && (alive || next < p.photonCount)) {
            suspended = true;
            break;
        }
    }
    if (suspended) {  // saved for the next dispatch, which the host makes while any is suspended
        resume[slot] = next;
        resume[slot + 1u] = alive ? 1u : 0u;
        resume[slot + 2u] = floatBitsToUint(s.pos.x);
        resume[slot + 3u] = floatBitsToUint(s.pos.y);
        resume[slot + 4u] = floatBitsToUint(s.pos.z);
        resume[slot + 5u] = floatBitsToUint(s.dir.x);
        resume[slot + 6u] = floatBitsToUint(s.dir.y);
        resume[slot + 7u] = floatBitsToUint(s.dir.z);
        resume[slot + 8u] = s.weight;
        resume[slot + 9u] = uint(s.pendingBin);
        resume[slot + 10u] = floatBitsToUint(s.pending);
        resume[slot + 11u] = rng.s0;
        resume[slot + 12u] = rng.s1;
        resume[slot + 13u] = rng.s2;
        resume[slot + 14u] = rng.s3;
        resume[slot + 15u] = floatBitsToUint(s.above.x);
        resume[slot + 16u] = floatBitsToUint(s.above.y);
        resume[slot + 17u] = floatBitsToUint(s.above.z);
        resume[slot + 18u] = floatBitsToUint(s.above.w);
        atomicAdd(resume[0], 1u);
    } else {
        resume[slot] = PHOTON_RESUME_DONE;
    }

    uint base = batch * PHOTON_TALLY_STRIDE;
    atomicAdd(tally[base + PHOTON_TALLY_SPECULAR], t.specular);
    atomicAdd(tally[base + PHOTON_TALLY_DIFFUSE], t.diffuse);
    atomicAdd(tally[base + PHOTON_TALLY_TRANSMITTED], t.transmitted);
    atomicAdd(tally[base + PHOTON_TALLY_ABSORBED], t.absorbed);
    atomicAdd(tally[base + PHOTON_TALLY_ESCAPED], t.escaped);
    atomicAdd(tally[base + PHOTON_TALLY_SCATTERINGS], t.scatterings);
    atomicAdd(tally[base + PHOTON_TALLY_WITHIN + 0u], t.within0);
    atomicAdd(tally[base + PHOTON_TALLY_WITHIN + 1u], t.within1);
    atomicAdd(tally[base + PHOTON_TALLY_WITHIN + 2u], t.within2);
    atomicAdd(tally[base + PHOTON_TALLY_WITHIN + 3u], t.within3);
    atomicAdd(tally[base + PHOTON_TALLY_INTERACTIONS], t.interactions);
    atomicAdd(tally[base + PHOTON_TALLY_ROULETTE_GAIN], t.rouletteGain);
    atomicAdd(tally[base + PHOTON_TALLY_ROULETTE_LOSS], t.rouletteLoss);
    if (photonControls(p, k)) {
        // The stride is a multiple of PHOTON_CONTROL_BATCHES: one control batch per invocation.
        uint c = PHOTON_CONTROL_OFFSET + ((p.photonStart + invocation) % PHOTON_CONTROL_BATCHES) * PHOTON_CONTROL_STRIDE;
        atomicAdd(tally[c + 0u], t.diffuse);
        atomicAdd(tally[c + 1u], t.transmitted);
        atomicAdd(tally[c + 2u], t.within0);
        atomicAdd(tally[c + 3u], t.within1);
        atomicAdd(tally[c + 4u], t.within2);
        atomicAdd(tally[c + 5u], t.within3);
        for (uint i = 0u; i < PHOTON_CONTROL_TERMS; ++i) atomicAdd(tally[c + 6u + i], t.controls[i]);
    }
}
