// Validation of a Monte Carlo setup, its push-constant block, and the statistics of a result.

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "photon_params.h"
#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/transport/beam_convolution.h"

namespace vpsim::transport {

namespace {

void require(bool ok, const std::string& key, const std::string& reason) {
    if (!ok) throw InputError(reason, "", key);
}

bool finite(double v) {
    return std::isfinite(v);
}

}  // namespace

const char* estimatorName(Estimator e) {
    switch (e) {
        case Estimator::Analog: return "analog";
        case Estimator::Implicit: return "implicit";
        case Estimator::ImplicitTrack: return "implicit-track";
        case Estimator::Track: return "track-length";
        case Estimator::Collision: return "collision";
    }
    return "track-length";
}

namespace {
constexpr Estimator ALL_ESTIMATORS[] = {Estimator::Analog, Estimator::Implicit,
                                        Estimator::ImplicitTrack, Estimator::Track,
                                        Estimator::Collision};
}

std::vector<std::string> estimatorNames() {
    std::vector<std::string> names;
    for (Estimator e : ALL_ESTIMATORS) names.push_back(estimatorName(e));
    return names;
}

Estimator parseEstimator(const std::string& text, const std::string& key) {
    for (Estimator e : ALL_ESTIMATORS)
        if (text == estimatorName(e)) return e;
    throw InputError(
        "estimator must be analog, implicit, implicit-track, track-length or "
        "collision, got '" +
            text + "'",
        "", key);
}

void validateSetup(const McSetup& s) {
    const auto& o = s.optics;
    require(finite(o.mua) && o.mua >= 0, "mua",
            "absorption coefficient must be >= 0, got " + formatNumber(o.mua));
    require(finite(o.mus) && o.mus >= 0, "mus",
            "scattering coefficient must be >= 0, got " + formatNumber(o.mus));
    require(finite(o.g) && o.g > -1 && o.g < 1, "g",
            "anisotropy g must lie in (-1, 1), got " + formatNumber(o.g));
    require(finite(o.refractiveIndex) && o.refractiveIndex >= 1, "refractive_index",
            "refractive index of the medium must be >= 1, got " + formatNumber(o.refractiveIndex));
    require(finite(s.nAbove) && s.nAbove >= 1, "n_outside", "refractive index above must be >= 1");
    require(finite(s.nBelow) && s.nBelow >= 1, "n_outside", "refractive index below must be >= 1");
    require(finite(s.thickness) && s.thickness >= 0, "thickness",
            "thickness must be >= 0 (0 = semi-infinite)");
    require(s.thickness > 0 || o.mua > 0 || s.lateralRadius > 0, "mua",
            "a semi-infinite medium needs mua > 0 (or a lateral radius) so that every photon ends");
    require(finite(s.lateralRadius) && s.lateralRadius >= 0, "lateral_radius",
            "lateral radius must be >= 0");
    if (s.beam == BeamShape::Gaussian)
        require(finite(s.w0) && s.w0 > 0, "w0",
                "Gaussian beam radius W0 must be > 0, got " + formatNumber(s.w0));
    require(s.photons >= 1 && s.photons <= MAX_PHOTONS, "photons",
            "photon count must be between 1 and " + std::to_string(MAX_PHOTONS) + ", got " +
                std::to_string(s.photons));
    require(s.firstPhoton <= MAX_PHOTONS, "first_photon",
            "first photon index must be at most " + std::to_string(MAX_PHOTONS));
    if (o.phase == optics::PhaseModel::Tabulated) {
        require(o.inverseCdf.size() >= 2, "phase",
                "tabulated phase function needs >= 2 inverse-CDF entries");
        for (float c : o.inverseCdf)
            require(std::isfinite(c) && c >= -1.0f && c <= 1.0f, "phase",
                    "inverse-CDF entries must be cos(theta) values in [-1, 1]");
    }
    const auto& b = s.bins;
    require(finite(b.rMax) && b.rMax > 0 && finite(b.zMax) && b.zMax > 0, "bins",
            "cylindrical tally extent rMax, zMax must be > 0");
    require(b.rBins >= 1 && b.zBins >= 1 && uint64_t(b.rBins) * b.zBins <= MAX_RZ_BINS, "bins",
            "cylindrical tally needs 1.." + std::to_string(MAX_RZ_BINS) + " bins, got " +
                std::to_string(uint64_t(b.rBins) * b.zBins));
    const auto& g = s.grid;
    if (g.nxy > 0) {
        require(finite(g.voxel) && g.voxel > 0, "grid.voxel", "Cartesian voxel size must be > 0");
        uint64_t voxels = uint64_t(g.nxy) * g.nxy * g.nz;
        if (g.nz == 0 || voxels > MAX_GRID_VOXELS)
            throw ResourceError("Cartesian absorption grid of " + std::to_string(voxels) +
                                " voxels (" + formatBytes(double(voxels) * 8) +
                                ") refused: use 1.." + std::to_string(MAX_GRID_VOXELS) + " voxels");
    }
    require(finite(s.rouletteThreshold) && s.rouletteThreshold > 0 && s.rouletteThreshold <= 0.1,
            "roulette_threshold",
            "roulette threshold must lie in (0, 0.1] of the launched weight, got " +
                formatNumber(s.rouletteThreshold));
    require(!s.binsPerBatch || uint64_t(b.rBins) * b.zBins * MC_BATCHES <= MAX_RZ_BINS, "bins",
            "per-batch cylindrical tallies need at most " +
                std::to_string(MAX_RZ_BINS / MC_BATCHES) + " bins");
    require(s.depths.size() <= 4, "depths",
            "at most 4 depths, got " + std::to_string(s.depths.size()));
    for (double d : s.depths)
        require(finite(d) && d > 0, "depths", "depths must be > 0, got " + formatNumber(d));
}

namespace {

/// Mean of cos(theta) sampled by linear interpolation of the inverse CDF at a uniform u: the
/// trapezoid rule over the table's equal steps in u.
double tableMeanCosine(const std::vector<float>& table) {
    double sum = 0;
    for (size_t i = 0; i + 1 < table.size(); ++i) sum += 0.5 * (double(table[i]) + table[i + 1]);
    return table.size() > 1 ? sum / double(table.size() - 1) : 0.0;
}

}  // namespace

glsl::PhotonParams makePhotonParams(const McSetup& s) {
    glsl::PhotonParams p{};
    p.seed = s.seed;
    p.photonStart = 0;
    p.photonCount = uint32_t(std::min<uint64_t>(s.photons, 0xffffffffu));
    p.photonStartHi = 0;
    p.invocationStride = 1;
    p.beamShape =
        s.beam == BeamShape::Gaussian ? glsl::PHOTON_BEAM_GAUSSIAN : glsl::PHOTON_BEAM_PENCIL;
    p.beamW0 = float(s.w0);
    p.mua = float(s.optics.mua);
    p.mus = float(s.optics.mus);
    bool table = s.optics.phase == optics::PhaseModel::Tabulated;
    // With a table, g is the mean cosine the step actually samples (the control variates'
    // scattering term needs that exactly; Henyey-Greenstein's mean cosine is g itself).
    p.g = float(table ? tableMeanCosine(makePhaseTable(s)) : s.optics.g);
    p.phaseModel = table ? glsl::PHOTON_PHASE_TABLE : glsl::PHOTON_PHASE_HG;
    p.phaseTableSize = table ? uint32_t(std::min(s.optics.inverseCdf.size(), MAX_PHASE_TABLE)) : 0u;
    p.nMedium = float(s.optics.refractiveIndex);
    p.nAbove = float(s.nAbove);
    p.nBelow = float(s.nBelow);
    p.thickness = float(s.thickness);
    p.lateralRadius = float(s.lateralRadius);
    // Specular reflection at normal entry (both beams are at normal incidence): split off as a
    // whole number of quanta, the same for every photon.
    double r = (s.nAbove - s.optics.refractiveIndex) / (s.nAbove + s.optics.refractiveIndex);
    double rsp = r * r;
    p.launchWeight = LAUNCH_WEIGHT;
    p.enteringWeight = LAUNCH_WEIGHT - uint32_t(std::llround(rsp * LAUNCH_WEIGHT));
    p.rBinWidth = float(s.bins.rMax / s.bins.rBins);
    p.zBinWidth = float(s.bins.zMax / s.bins.zBins);
    p.rBins = s.bins.rBins;
    p.zBins = s.bins.zBins;
    p.gridVoxel = float(s.grid.voxel);
    p.gridNxy = s.grid.nxy;
    p.gridNz = s.grid.nxy > 0 ? s.grid.nz : 0u;
    float depth[4] = {-1.0f, -1.0f, -1.0f, -1.0f};  // unused slots: nothing lies above z < 0
    for (size_t k = 0; k < s.depths.size() && k < 4; ++k) depth[k] = float(s.depths[k]);
    p.depth0 = depth[0];
    p.depth1 = depth[1];
    p.depth2 = depth[2];
    p.depth3 = depth[3];
    switch (s.estimator) {
        case Estimator::Analog: p.estimator = glsl::PHOTON_ESTIMATOR_ANALOG; break;
        case Estimator::Implicit: p.estimator = glsl::PHOTON_ESTIMATOR_IMPLICIT; break;
        case Estimator::ImplicitTrack: p.estimator = glsl::PHOTON_ESTIMATOR_IMPLICIT_TRACK; break;
        case Estimator::Track: p.estimator = glsl::PHOTON_ESTIMATOR_TRACK; break;
        case Estimator::Collision: p.estimator = glsl::PHOTON_ESTIMATOR_COLLISION; break;
    }
    if (s.binsPerBatch) p.estimator |= glsl::PHOTON_FLAG_BATCH_BINS;
    if (s.controlVariates) p.estimator |= glsl::PHOTON_FLAG_CONTROLS;
    // At least 1 quantum: a photon of weight 0 must end.
    p.rouletteWeight = std::max(1u, uint32_t(std::llround(s.rouletteThreshold * LAUNCH_WEIGHT)));
    return p;
}

std::vector<float> makePhaseTable(const McSetup& s) {
    if (s.optics.phase != optics::PhaseModel::Tabulated) return {};
    const auto& in = s.optics.inverseCdf;
    if (in.size() <= MAX_PHASE_TABLE) return in;
    // Resample the inverse CDF (linear in u) onto MAX_PHASE_TABLE points.
    std::vector<float> out(MAX_PHASE_TABLE);
    for (size_t i = 0; i < out.size(); ++i) {
        double x = double(i) / double(out.size() - 1) * double(in.size() - 1);
        size_t j = std::min(size_t(x), in.size() - 2);
        double f = x - double(j);
        out[i] = float(in[j] * (1 - f) + in[j + 1] * f);
    }
    return out;
}

uint64_t photonsInBatch(uint64_t first, uint64_t photons, int batch, int batches) {
    // Indices i < n with i % B == b number ceil((n - b) / B).
    auto below = [batch, batches](uint64_t n) {
        return n > uint64_t(batch) ? (n - uint64_t(batch) + batches - 1) / batches : 0;
    };
    return below(first + photons) - below(first);
}

void setBins(McResult& result, std::vector<uint64_t> words, const glsl::PhotonParams& params) {
    if (result.setup.unscaledBins) {  // a rank's share: mc_split.cpp adds and scales
        result.absorbedRZ = std::move(words);
        return;
    }
    if ((params.estimator & 255u) == glsl::PHOTON_ESTIMATOR_COLLISION) {
        const double mut = double(params.mua) + double(params.mus);
        const double quanta =
            mut > 0 ? double(params.enteringWeight) * double(params.mua) / mut : 0;
        for (uint64_t& w : words) w = uint64_t(std::llround(double(w) * quanta));
    }
    if (!result.setup.binsPerBatch) {
        result.absorbedRZ = std::move(words);
        return;
    }
    const size_t bins = words.size() / MC_BATCHES;
    result.absorbedRZ.assign(bins, 0);
    for (size_t b = 0; b < size_t(MC_BATCHES); ++b)
        for (size_t i = 0; i < bins; ++i) result.absorbedRZ[i] += words[b * bins + i];
    result.absorbedRZBatches = std::move(words);
}

// ---------------------------------------------------------------------------------- McResult

BatchTally McResult::total() const {
    BatchTally t;
    for (const auto& b : batches) t += b;
    return t;
}

uint64_t McResult::launched() const {
    return total().photons * launchWeight;
}

namespace {

/// Standard error of the photon-weighted mean `mean` of per-batch values, from their spread
/// (empty batches left out).
double batchStandardError(const McResult& r, const std::array<double, MC_BATCHES>& values,
                          double mean) {
    int used = 0;
    double squares = 0;
    for (int b = 0; b < MC_BATCHES; ++b) {
        if (r.batches[size_t(b)].photons == 0) continue;
        squares += (values[size_t(b)] - mean) * (values[size_t(b)] - mean);
        ++used;
    }
    return used > 1 ? std::sqrt(squares / (double(used) * (used - 1))) : 0.0;
}

/// A tally (get: a batch's quanta, an integer, or a double for signed ones) as a fraction of the
/// launched weight: the mean over all photons (exact for integer tallies: summed as integers) and
/// the standard error from the spread of the batch means.
template <class Get>
Fraction batchFraction(const McResult& r, Get get) {
    Fraction f;
    const uint64_t launched = r.launched();
    if (launched == 0) return f;
    std::array<double, MC_BATCHES> values{};
    decltype(get(r.batches[0])) sum = 0;
    for (int b = 0; b < MC_BATCHES; ++b) {
        const BatchTally& t = r.batches[size_t(b)];
        sum += get(t);
        if (t.photons > 0) values[size_t(b)] = double(get(t)) / double(t.photons * r.launchWeight);
    }
    f.value = double(sum) / double(launched);
    f.standardError = batchStandardError(r, values, f.value);
    return f;
}

}  // namespace

Fraction fractionOfBatches(const McResult& r, const std::array<double, MC_BATCHES>& values) {
    Fraction f;
    double photons = 0, sum = 0;
    for (int b = 0; b < MC_BATCHES; ++b) {
        const double n = double(r.batches[size_t(b)].photons);
        photons += n;
        sum += n * values[size_t(b)];
    }
    if (photons == 0) return f;
    f.value = sum / photons;
    f.standardError = batchStandardError(r, values, f.value);
    return f;
}

Fraction McResult::specular() const {
    return batchFraction(*this, [](const BatchTally& b) { return b.specular; });
}
Fraction McResult::diffuseTally() const {
    return batchFraction(*this, [](const BatchTally& b) { return b.diffuse; });
}
Fraction McResult::transmittedTally() const {
    return batchFraction(*this, [](const BatchTally& b) { return b.transmitted; });
}
Fraction McResult::absorbedTally() const {
    return batchFraction(*this, [](const BatchTally& b) { return b.absorbed; });
}
Fraction McResult::escaped() const {
    return batchFraction(*this, [](const BatchTally& b) { return b.escaped; });
}
Fraction McResult::absorbedWithinTally(size_t k) const {
    if (k >= 4)
        throw InputError("depth index " + std::to_string(k) + " out of range 0..3", "", "depths");
    return batchFraction(*this, [k](const BatchTally& b) { return b.absorbedWithin[k]; });
}

Fraction McResult::rouletteNet() const {
    // Signed: (gain - loss) per batch through doubles (each is exact below 2^53 quanta per batch).
    return batchFraction(
        *this, [](const BatchTally& b) { return double(b.rouletteGain) - double(b.rouletteLoss); });
}

double McResult::interactionsPerPhoton() const {
    BatchTally t = total();
    return t.photons ? double(t.interactions) / double(t.photons) : 0.0;
}

double McResult::scatteringsPerPhoton() const {
    BatchTally t = total();
    return t.photons ? double(t.scatterings) / double(t.photons) : 0.0;
}

double McResult::photonsPerSecond() const {
    return seconds > 0 ? double(total().photons) / seconds : 0.0;
}

bool McResult::energyBalanced() const {
    BatchTally t = total();
    return t.photons * launchWeight + t.rouletteGain ==
           t.specular + t.diffuse + t.transmitted + t.absorbed + t.escaped + t.rouletteLoss;
}

nlohmann::json McResult::summaryJson() const {
    nlohmann::json j;
    auto put = [&j](const std::string& name, const Fraction& f) {
        j[name] = f.value;
        j[name + "_stderr"] = f.standardError;
    };
    j["photons"] = total().photons;
    put("specular_reflectance", specular());
    put("diffuse_reflectance", diffuse());
    put("transmittance", transmitted());
    put("absorbed", absorbed());
    if (setup.lateralRadius > 0) put("escaped", escaped());
    j["estimator"] = estimatorName(setup.estimator);
    j["control_variates"] = controlled();  // diffuse, transmittance, absorbed(_within) controlled
    if (controlled()) put("diffuse_reflectance_tally", diffuseTally());
    j["beam_convolved"] = convolvesBeam(setup);
    if (setup.estimator == Estimator::Implicit || setup.estimator == Estimator::ImplicitTrack) {
        j["roulette_threshold"] = setup.rouletteThreshold;
        put("roulette_net", rouletteNet());
    }
    j["scatterings_per_photon"] = scatteringsPerPhoton();
    j["interactions_per_photon"] = interactionsPerPhoton();
    j["photons_per_second"] = photonsPerSecond();
    j["seconds"] = seconds;
    j["backend"] = backend;
    j["energy_balanced"] = energyBalanced();
    if (!setup.depths.empty()) {
        nlohmann::json depths = nlohmann::json::array(), within = nlohmann::json::array(),
                       withinErr = nlohmann::json::array();
        for (size_t k = 0; k < setup.depths.size(); ++k) {
            Fraction f = absorbedWithin(k);
            depths.push_back(setup.depths[k] * 1000.0);
            within.push_back(f.value);
            withinErr.push_back(f.standardError);
        }
        j["depths_um"] = depths;
        j["absorbed_within"] = within;
        j["absorbed_within_stderr"] = withinErr;
    }
    return j;
}

}  // namespace vpsim::transport
