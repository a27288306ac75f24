// Types and constants of the photon Monte Carlo shared by shaders/photon_mc.comp and the CPU path
// (src/transport/mc_cpu.cpp includes this through include/vpsim/core/glsl_shim.h).
// PhotonParams is the push-constant block: only 4-byte scalars, 32 of them = 128 bytes (the
// Vulkan minimum push-constant size), so std430 and C++ layouts agree member by member.
#ifndef VPSIM_PHOTON_TYPES
#define VPSIM_PHOTON_TYPES

// Beam shapes (PhotonParams.beamShape).
const uint PHOTON_BEAM_PENCIL = 0u;
const uint PHOTON_BEAM_GAUSSIAN = 1u;
// Phase functions (PhotonParams.phaseModel).
const uint PHOTON_PHASE_HG = 0u;
const uint PHOTON_PHASE_TABLE = 1u;

// What one photon step ended with.
const int PHOTON_EVENT_MOVED = 0;        // hopped, or was internally reflected at a boundary
const int PHOTON_EVENT_SCATTERED = 1;    // interacted and was scattered (photon lives on)
const int PHOTON_EVENT_ABSORBED = 2;     // interacted and was absorbed (analog absorption)
const int PHOTON_EVENT_REFLECTED = 3;    // left through the top surface z = 0 (diffuse reflectance)
const int PHOTON_EVENT_TRANSMITTED = 4;  // left through the bottom surface z = thickness
const int PHOTON_EVENT_ESCAPED = 5;      // interacted outside the lateral radius (left sideways)

// Estimators (low byte of PhotonParams.estimator).
// ANALOG: a photon is absorbed whole at an interaction with probability mua/mut; the (r,z) bins
//   and the depth tallies count absorption points.
// IMPLICIT: implicit capture (at every interaction the fraction mua/mut of the weight is deposited
//   and the photon always scatters) with Russian roulette below PhotonParams.rouletteWeight; bins
//   and depth tallies count the deposits (collision estimator).
// IMPLICIT_TRACK: the same transport; bins and depth tallies by the track-length estimator
//   (mua x weight x path length inside each bin, or above each depth).
// TRACK: analog transport (cheap photons), bins by the track-length estimator, depth tallies by
//   the absorption points (as ANALOG).
// COLLISION: analog transport, bins by the collision estimator of the expected absorption (every
//   interaction adds weight x mua/mut to its bin, whether or not the photon is absorbed there),
//   depth tallies by the absorption points. Same expectation as TRACK (the collision density is
//   mut times the track density), one bin lookup per interaction instead of one per bin crossed.
//   Analog transport keeps every photon's weight at the entering weight, so each interaction adds
//   the same amount: the shaders count interactions per bin, and the host multiplies the counts
//   by enteringWeight x mua/mut in double (exact, and no fraction to carry per photon).
const uint PHOTON_ESTIMATOR_ANALOG = 0u;
const uint PHOTON_ESTIMATOR_IMPLICIT = 1u;
const uint PHOTON_ESTIMATOR_IMPLICIT_TRACK = 2u;
const uint PHOTON_ESTIMATOR_TRACK = 3u;
const uint PHOTON_ESTIMATOR_COLLISION = 4u;
// PhotonParams.estimator flag: the (r,z) bins are kept per batch (PHOTON_BATCHES copies).
const uint PHOTON_FLAG_BATCH_BINS = 256u;
// PhotonParams.estimator flag (GPU): continue the photons suspended by the previous dispatch.
const uint PHOTON_FLAG_RESUME = 512u;
// PhotonParams.estimator flag: tally the control variates (COLLISION and TRACK only).
const uint PHOTON_FLAG_CONTROLS = 1024u;
// Work (photon steps plus bin crossings) one GPU invocation does per dispatch before it saves its
// photon and stops: lavapipe silently ends a shader after 65535 loop iterations (gallivm's loop
// limiter), which lost the photons of very turbid media (issue 14: mus = 1e7/cm).
const uint PHOTON_WORK_BUDGET = 30000u;
// Resume buffer: word 0 counts the invocations suspended by the last dispatch; invocation i's
// photon state is at PHOTON_RESUME_HEADER + i * PHOTON_RESUME_SLOT.
const uint PHOTON_RESUME_HEADER = 4u;
const uint PHOTON_RESUME_SLOT = 20u;
const uint PHOTON_RESUME_DONE = 4294967295u;  // slot word 0 of an invocation with nothing left
// Russian roulette: a photon below the threshold survives with probability 1/PHOTON_ROULETTE_GAIN
// and then carries PHOTON_ROULETTE_GAIN times its weight (MCML's CHANCE = 0.1).
const uint PHOTON_ROULETTE_GAIN = 10u;

// Layout of the tally buffer (uint64 words): PHOTON_BATCHES batches of PHOTON_TALLY_STRIDE
// counters, then the absorbed weight in rBins x zBins cylindrical bins (index iz * rBins + ir).
// Photon i belongs to batch i % PHOTON_BATCHES; the batches give the standard errors.
const uint PHOTON_BATCHES = 64u;
const uint PHOTON_TALLY_SPECULAR = 0u;
const uint PHOTON_TALLY_DIFFUSE = 1u;
const uint PHOTON_TALLY_TRANSMITTED = 2u;
const uint PHOTON_TALLY_ABSORBED = 3u;
const uint PHOTON_TALLY_ESCAPED = 4u;
const uint PHOTON_TALLY_SCATTERINGS = 5u;   // a count of scattering events, not weight
const uint PHOTON_TALLY_WITHIN = 6u;        // 4 counters: weight absorbed above depth0..depth3
const uint PHOTON_TALLY_INTERACTIONS = 10u; // a count of interactions (absorptions included)
const uint PHOTON_TALLY_ROULETTE_GAIN = 11u;  // weight created by roulette survivors
const uint PHOTON_TALLY_ROULETTE_LOSS = 12u;  // weight of photons ended by roulette
const uint PHOTON_MAX_DEPTHS = 4u;
const uint PHOTON_TALLY_STRIDE = 13u;
// Then (analog-transport estimators with control variates) PHOTON_CONTROL_BATCHES control batches
// of PHOTON_CONTROL_STRIDE words: photon i is in control batch i % PHOTON_CONTROL_BATCHES (a
// refinement of the batches), which holds its diffuse, transmitted and 4 absorbed-within quanta
// and its PHOTON_CONTROL_TERMS control sums: enough samples to fit the controls' coefficients.
const uint PHOTON_CONTROL_OFFSET = 832u;    // PHOTON_BATCHES * PHOTON_TALLY_STRIDE
const uint PHOTON_CONTROL_BATCHES = 1024u;
const uint PHOTON_CONTROL_STRIDE = 16u;     // 6 tallies + PHOTON_CONTROL_TERMS
const uint PHOTON_BIN_OFFSET = 17216u;      // + PHOTON_CONTROL_BATCHES * PHOTON_CONTROL_STRIDE

// Control variates of the analog-transport estimators (photon_control.glsl): the terms, each a
// sum over the photon's stages of (what happened) - (its exact expectation given the state
// before), in units of 2^-32 (two's complement in the uint64 tally words). Words 6.. of a control
// batch.
const uint PHOTON_CONTROL_ARRIVE_TOP = 0u;      // a flight reaches z = 0
const uint PHOTON_CONTROL_ARRIVE_BOTTOM = 1u;   // a flight reaches z = thickness
const uint PHOTON_CONTROL_LEAVE_TOP = 2u;       // a photon at z = 0 leaves (is not reflected)
const uint PHOTON_CONTROL_LEAVE_BOTTOM = 3u;    // the same at z = thickness
const uint PHOTON_CONTROL_FLIGHT = 4u;          // exp(-kappa z) at the next interaction
const uint PHOTON_CONTROL_FLIGHT_UZ = 5u;       // uz exp(-kappa z) at the next interaction
const uint PHOTON_CONTROL_ABSORB = 6u;          // exp(-kappa z) if the photon survives
const uint PHOTON_CONTROL_ABSORB_UZ = 7u;       // uz exp(-kappa z) if it survives
const uint PHOTON_CONTROL_SCATTER = 8u;         // exp(-kappa z) x the new uz
const uint PHOTON_CONTROL_ARRIVE_TOP_LEAVING = 9u;  // reaches z = 0, times its chance to leave
const uint PHOTON_CONTROL_TERMS = 10u;

// Everything one dispatch needs; lengths in mm, coefficients in 1/mm.
struct PhotonParams {
    uint seed;              // run seed; photon i draws from photonStream(seed, i)
    uint photonStart;       // first photon index of this dispatch (low 32 bits)
    uint photonCount;       // photons of this dispatch
    uint invocationStride;  // invocations of this dispatch (a multiple of PHOTON_BATCHES)
    uint beamShape;         // PHOTON_BEAM_*
    float beamW0;           // Gaussian beam 1/e^2 intensity radius
    float mua;              // absorption coefficient
    float mus;              // scattering coefficient
    float g;                // Henyey-Greenstein asymmetry
    uint phaseModel;        // PHOTON_PHASE_*
    uint phaseTableSize;    // entries of the inverse CDF table (>= 2 when tabulated)
    float nMedium;          // refractive index inside the medium
    float nAbove;           // refractive index above z = 0
    float nBelow;           // refractive index below z = thickness
    float thickness;        // slab thickness; 0 = semi-infinite
    float lateralRadius;    // photons interacting beyond this radius escape sideways; 0 = unbounded
    uint launchWeight;      // weight quanta of one launched photon
    uint enteringWeight;    // quanta that enter the medium (launchWeight minus specular part)
    float rBinWidth;        // cylindrical tally bin sizes
    float zBinWidth;
    uint rBins;
    uint zBins;
    float gridVoxel;        // Cartesian tally voxel edge; grid centred on the beam axis
    uint gridNxy;           // voxels along x and y (0 = no Cartesian tally)
    uint gridNz;            // voxels along z, from z = 0
    float depth0;           // depths for the "absorbed above depth" tallies
    float depth1;
    float depth2;
    float depth3;
    uint rouletteWeight;    // quanta below which implicit-capture photons play roulette
    uint photonStartHi;     // high 32 bits of the first photon index (budgets above 2^32)
    uint estimator;         // PHOTON_ESTIMATOR_* | PHOTON_FLAG_*
};

// One photon in flight (never stored in a buffer).
struct PhotonState {
    vec3 pos;        // mm, z = 0 at the top surface, +z into the medium
    vec3 dir;        // unit direction
    uint weight;     // quanta the photon carries (implicit capture lowers it at interactions)
    int pendingBin;  // track-length estimator: bin of the not yet flushed deposit, -1 = none
    float pending;   // quanta pending for pendingBin (or the carried fraction of a quantum)
    vec4 above;      // track-length depth tallies of this photon (quanta above depth0..3)
    float depthFactor;  // control variates: photonExp(-kappa pos.z), kept so each flight needs one
};

#endif
