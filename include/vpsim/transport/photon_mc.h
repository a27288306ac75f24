#pragma once
/// @file
/// Photon Monte Carlo of light entering a turbid medium (seed 000 Section II-B): a pencil or
/// Gaussian beam at normal incidence on a slab or a semi-infinite medium, Fresnel reflection at
/// both surfaces, absorption by one of three estimators (Estimator), scattering by
/// Henyey-Greenstein or a tabulated (Mie) phase function. The physics is
/// shaders/include/photon_step.glsl, run by a Vulkan compute shader or by the CPU (TBB) from the
/// same source.
///
/// Weight is counted in integer quanta: a launched photon carries McResult::launchWeight quanta,
/// the specular part is split off at entry, and the rest ends in diffuse reflectance,
/// transmittance, absorption, lateral escape or (implicit capture) Russian roulette. Hence
/// launched + rouletteGain = specular + diffuse + transmitted + absorbed + escaped + rouletteLoss
/// holds exactly (the roulette terms are 0 for the analog estimator).
/// Photon i uses the random stream rngSeed(seed, i), so a seed gives the same integer tallies on
/// any thread count; the CPU and GPU agree within statistics (their log/sin/cos differ in the
/// last bits, so individual trajectories eventually part).

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/optics/material.h"

namespace vpsim::gpu {
class Context;
}

namespace vpsim::transport {

/// Beam at normal incidence: a pencil on the axis, or Gaussian of 1/e^2 intensity radius W0 (Eq.
/// 6).
enum class BeamShape { Pencil, Gaussian };

/// Cylindrical (r, z) bins for the absorbed weight: rBins x zBins bins of rMax/rBins by
/// zMax/zBins, r from the beam axis, z from the top surface. Absorption outside still counts in
/// the totals.
struct CylindricalGrid {
    double rMax = 0.2;  ///< mm
    double zMax = 0.2;  ///< mm
    uint32_t rBins = 40;
    uint32_t zBins = 40;
};

/// Optional Cartesian tally: nxy x nxy x nz voxels of edge `voxel`, centred on the beam axis in x
/// and y, from z = 0 down. nxy == 0 switches it off.
struct CartesianGrid {
    double voxel = 0.005;  ///< mm
    uint32_t nxy = 0;
    uint32_t nz = 0;
};

/// How absorption is scored (see shaders/include/photon_types.glsl).
enum class Estimator {
    Analog,         ///< a photon is absorbed whole with probability mua/mut; point tallies
    Implicit,       ///< implicit capture + Russian roulette; collision tallies (MCML's)
    ImplicitTrack,  ///< implicit capture + roulette; track-length bins and depth tallies
    Track,          ///< analog transport, track-length bins, point depth tallies
    Collision,      ///< analog transport, collision-estimated bins, point depth tallies (default)
};  /// "analog", "implicit", "implicit-track", "track-length" or "collision". The totals (R, T,
/// absorbed) are exact integer partitions for every estimator; the (r,z) bins of the track-length
/// and collision ones (and McResult::absorbedWithin of implicit-track) are track-length or
/// collision estimates, which match the totals only within statistics.
const char* estimatorName(Estimator e);
/// Every estimator's name, for command-line choices.
std::vector<std::string> estimatorNames();
/// Parses estimatorName's spellings. @throw InputError naming `key` for anything else.
Estimator parseEstimator(const std::string& text, const std::string& key = "estimator");

/// Default roulette threshold of the implicit-capture estimators, as a fraction of the launched
/// weight (10x MCML's 1e-4, so photons end sooner; not tuned: bench_photon_mc's MCML reference
/// keeps 1e-4).
constexpr double DEFAULT_ROULETTE_THRESHOLD = 1e-3;

/// One Monte Carlo run.
struct McSetup {
    optics::MediumOptics optics;  ///< medium (mua, mus in 1/mm, g, refractive index, phase)
    double thickness = 0.0;       ///< slab thickness, mm; 0 = semi-infinite
    double nAbove = 1.0;          ///< refractive index above the top surface
    double nBelow = 1.0;          ///< refractive index below the slab (unused when semi-infinite)
    BeamShape beam = BeamShape::Pencil;
    double w0 = 0.05;            ///< Gaussian beam 1/e^2 intensity radius W0 (Eq. 6), mm
    double lateralRadius = 0.0;  ///< photons interacting beyond this radius escape; 0 = unbounded
    uint64_t photons = 100000;   ///< photons launched (at most MAX_PHOTONS)
    /// Index of the first photon: the run traces photons [firstPhoton, firstPhoton + photons),
    /// photon i with its own random stream and in batch i % MC_BATCHES, so disjoint ranges
    /// (other machines, other runs) add up to one larger run.
    uint64_t firstPhoton = 0;
    uint32_t seed = 1;
    CylindricalGrid bins;
    CartesianGrid grid;
    std::vector<double> depths;  ///< up to 4 depths (mm) for McResult::absorbedWithin
    Estimator estimator = Estimator::Collision;
    /// Implicit capture: photons below this fraction of the launched weight play roulette
    /// (survive 1 in 10 with 10x the weight). In (0, 0.1].
    double rouletteThreshold = DEFAULT_ROULETTE_THRESHOLD;
    /// Keep the (r,z) bins per batch (McResult::absorbedRZBatches), for their standard errors.
    bool binsPerBatch = false;
    /// Gaussian beams: trace the pencil-beam response and convolve it with the beam profile
    /// (src/transport/beam_convolution.h): the same expected (r,z) bins with less variance near
    /// the axis. Applies when there is no lateral radius and no Cartesian grid and W0 spans at
    /// least 4 radial bins; the totals are the same tallies either way.
    bool beamConvolution = true;
    /// Collision and track-length estimators: tally control variates for the diffuse
    /// reflectance, the transmittance and the absorbed-within fractions (McResult::diffuse). The
    /// bins and the integer tallies are the same either way; the step costs about 50% more
    /// (bench_photon_mc), so runs that only need the bins (the beam kernel) switch it off.
    bool controlVariates = true;
    /// Keep the (r,z) words as tallied (the collision estimator's are interaction counts,
    /// scaled to quanta with rounding): set by runs split over ranks (transport/mc_split.h),
    /// which add the words of all ranks and scale the sum once, as one process would.
    bool unscaledBins = false;
};

/// Most photons one run may launch (64-bit indices; the launched weight, photons x 2^24
/// quanta, must fit 64 bits).
constexpr uint64_t MAX_PHOTONS = 1000000000000ull;
/// Batches used for the standard errors (photon i is in batch i % MC_BATCHES).
constexpr int MC_BATCHES = 64;
/// Control-variate terms the collision and track-length estimators tally
/// (shaders/include/photon_control.glsl), in control batches: photon i is in control batch
/// i % MC_CONTROL_BATCHES (so in batch i % MC_BATCHES too).
constexpr int MC_CONTROL_TERMS = 10;
constexpr int MC_CONTROL_BATCHES = 1024;

/// A fraction of the launched weight with its standard error from the batch spread.
struct Fraction {
    double value = 0.0;
    double standardError = 0.0;
};

/// Integer tallies of one batch, in weight quanta (scatterings and interactions are counts).
struct BatchTally {
    uint64_t photons = 0, specular = 0, diffuse = 0, transmitted = 0, absorbed = 0, escaped = 0,
             scatterings = 0, interactions = 0, rouletteGain = 0, rouletteLoss = 0;
    std::array<uint64_t, 4> absorbedWithin{};

    BatchTally& operator+=(const BatchTally& o) {
        photons += o.photons;
        specular += o.specular;
        diffuse += o.diffuse;
        transmitted += o.transmitted;
        absorbed += o.absorbed;
        escaped += o.escaped;
        scatterings += o.scatterings;
        interactions += o.interactions;
        rouletteGain += o.rouletteGain;
        rouletteLoss += o.rouletteLoss;
        for (size_t k = 0; k < absorbedWithin.size(); ++k) absorbedWithin[k] += o.absorbedWithin[k];
        return *this;
    }
};

/// Tallies of one control batch: the controlled tallies (quanta) and the control-variate sums
/// (units of 2^-32; each has mean zero).
struct ControlTally {
    uint64_t diffuse = 0, transmitted = 0;
    std::array<uint64_t, 4> absorbedWithin{};
    std::array<int64_t, MC_CONTROL_TERMS> controls{};

    ControlTally& operator+=(const ControlTally& o) {
        diffuse += o.diffuse;
        transmitted += o.transmitted;
        for (size_t k = 0; k < absorbedWithin.size(); ++k) absorbedWithin[k] += o.absorbedWithin[k];
        for (size_t c = 0; c < controls.size(); ++c) controls[c] += o.controls[c];
        return *this;
    }
};

/// Tallies of a run and the fractions derived from them (all fractions are of the launched weight).
struct McResult {
    McSetup setup;              ///< the setup that produced it
    uint64_t launchWeight = 0;  ///< quanta per launched photon
    std::array<BatchTally, MC_BATCHES> batches;
    /// MC_CONTROL_BATCHES control batches when controlled(), else empty.
    std::vector<ControlTally> controlBatches;
    std::vector<uint64_t> absorbedRZ;  ///< quanta per cylindrical bin, [iz * rBins + ir]
    /// With setup.binsPerBatch: MC_BATCHES copies of absorbedRZ, [b * rBins * zBins + bin].
    std::vector<uint64_t> absorbedRZBatches;
    std::vector<uint64_t> absorbedGrid;  ///< quanta per Cartesian voxel, [(iz*nxy+iy)*nxy+ix]
    double seconds = 0.0;                ///< wall time of the run
    std::string backend;                 ///< "cpu (N threads)" or the Vulkan device name

    /// Sum over the batches.
    BatchTally total() const;
    /// Launched weight of all photons, in quanta.
    uint64_t launched() const;
    Fraction specular() const;  ///< reflected at entry (Fresnel, normal incidence)
    /// Scattered back out through the top surface. With control variates (controlled()) the
    /// tally less a fitted combination of the batches' control sums (src/transport/mc_control.cpp):
    /// the same expectation, several times less variance; diffuseTally() is the plain tally.
    Fraction diffuse() const;
    /// Left through the bottom of a slab (scattered or not); controlled as diffuse().
    Fraction transmitted() const;
    /// Absorbed anywhere (inside the bins or not). With control variates: what the controlled
    /// diffuse() and transmitted() leave (entering - diffuse - transmitted - escaped), so the
    /// reported fractions still add up to 1.
    Fraction absorbed() const;
    Fraction escaped() const;  ///< interacted beyond setup.lateralRadius
    /// The exact integer tallies behind diffuse(), transmitted() and absorbed().
    Fraction diffuseTally() const;
    Fraction transmittedTally() const;
    Fraction absorbedTally() const;
    /// Whether the run tallied control variates (setup.controlVariates with the collision or
    /// track-length estimator).
    bool controlled() const;
    /// Per-batch values (fraction of each batch's launched weight) behind diffuse() and
    /// transmitted(); each batch's controls are fitted on the control batches of the other
    /// parity.
    std::array<double, MC_BATCHES> diffuseBatches() const;
    std::array<double, MC_BATCHES> transmittedBatches() const;
    std::array<double, MC_BATCHES> absorbedWithinBatches(size_t k) const;
    /// Fraction of launched weight absorbed at depths < setup.depths[k].
    /// With control variates, corrected as diffuse() (the same terms: about 2x less variance).
    Fraction absorbedWithin(size_t k) const;
    Fraction absorbedWithinTally(size_t k) const;  ///< the plain tally behind absorbedWithin(k)
    /// Net weight created by roulette, (gain - loss) / launched: 0 in expectation.
    Fraction rouletteNet() const;
    double scatteringsPerPhoton() const;
    /// Interactions (scatterings and absorptions) per launched photon.
    double interactionsPerPhoton() const;
    /// Launched photons over the wall time of the run (setup, transfers and tallies included).
    double photonsPerSecond() const;
    /// launched + rouletteGain == specular + diffuse + transmitted + absorbed + escaped +
    /// rouletteLoss, in integers.
    bool energyBalanced() const;
    /// The fractions, errors and rates as JSON (the `vpsim mc --json` fields).
    nlohmann::json summaryJson() const;
};

/// Checks a setup. @throw InputError naming the field and the reason.
void validateSetup(const McSetup& setup);

/// Runs the Monte Carlo on the Vulkan device `context`, or on the CPU (TBB) when it is null or
/// lacks 64-bit buffer atomics (with a warning). Shows progress for long runs.
/// @throw InputError for a bad setup; ResourceError when tallies exceed memory or buffer limits;
///        GpuError when the device fails.
McResult runPhotonMc(const McSetup& setup, const std::shared_ptr<gpu::Context>& context);
/// The CPU path. @param threads 0 = all cores, else this many threads (at most the core count).
McResult runPhotonMcCpu(const McSetup& setup, int threads = 0);
/// The Vulkan path. @throw GpuError when the device fails or lacks shaderInt64 and
/// shaderBufferInt64Atomics; InputError, ResourceError as runPhotonMc.
McResult runPhotonMcGpu(const McSetup& setup, const std::shared_ptr<gpu::Context>& context);

/// Writes the Cartesian absorption tally as an OpenVDB float grid "absorbed_fraction" (fraction of
/// launched weight per voxel; voxel size in mm, index origin at the beam axis).
/// @throw InputError when the run had no Cartesian grid or the file cannot be written.
void writeAbsorptionVdb(const std::string& path, const McResult& result);

}  // namespace vpsim::transport
