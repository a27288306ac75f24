#include "vpsim/validate/feature_probe.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"

namespace vpsim::validate {

std::vector<FeatureProbe> featureProbesFromConfig(const std::vector<ConfigNode>& entries) {
    std::vector<FeatureProbe> probes;
    for (const ConfigNode& f : entries) {
        FeatureProbe probe;
        probe.name = f.string("name");
        probe.x = f.quantity("x", dim::LENGTH);
        probe.y = f.quantity("y", dim::LENGTH);
        probe.zMin = f.quantity("z_min", dim::LENGTH);
        probe.zMax = f.quantity("z_max", dim::LENGTH);
        if (!(probe.zMax > probe.zMin)) throw f.error("z_max", "must be above z_min");
        probe.gap = f.choice("kind", {"gap", "solid"}) == "gap";
        probe.objective = f.quantity("objective", dim::LENGTH);
        if (f.has("measured"))
            for (const auto& m : f.raw("measured")) {
                if (!m.is_number()) throw f.error("measured", "expected a list of lengths in mm");
                probe.measured.push_back(m.get<double>());
            }
        probes.push_back(probe);
    }
    return probes;
}

FeatureProbes::FeatureProbes(std::vector<FeatureProbe> probes, const exposure::ExposureGrid& grid,
                             const cure::CureLaw& law, double voxelHeight)
    : mProbes(std::move(probes)),
      mGrid(grid),
      mLaw(&law),
      mVoxelHeight(voxelHeight),
      mLength(mProbes.size(), 0.0) {
    for (const auto& p : mProbes) {
        double i = (p.x - grid.originX) / grid.pitch, j = (p.y - grid.originY) / grid.pitch;
        if (i < 0 || j < 0 || i >= grid.nx || j >= grid.ny)
            throw InputError("feature probe '" + p.name + "' lies outside the simulated region");
        if (!(p.zMax > p.zMin))
            throw InputError("feature probe '" + p.name + "' needs z_max > z_min");
    }
}

void FeatureProbes::add(const exposure::ExposureSlice& slice) {
    for (size_t n = 0; n < mProbes.size(); ++n) {
        const FeatureProbe& p = mProbes[n];
        if (slice.z < p.zMin || slice.z > p.zMax) continue;
        int i = int((p.x - mGrid.originX) / mGrid.pitch),
            j = int((p.y - mGrid.originY) / mGrid.pitch);
        if (!slice.owned().contains(i, j)) continue;  // another tile's cell
        const exposure::SurfaceGrid& values = *slice.values;
        bool cured = mLaw->isCured(values.at(i - values.firstI, j - values.firstJ));
        if (cured != p.gap) mLength[n] += mVoxelHeight;
    }
}

void FeatureProbes::restoreState(const std::vector<double>& lengths) {
    if (lengths.size() != mProbes.size())
        throw InputError("the saved feature lengths are not one per feature probe");
    mLength = lengths;
}

void FeatureProbes::mergeState(const std::vector<double>& lengths) {
    if (lengths.size() != mProbes.size())
        throw InputError("the saved feature lengths are not one per feature probe");
    for (size_t n = 0; n < lengths.size(); ++n) mLength[n] += lengths[n];
}

nlohmann::json FeatureMeasurements::toJson() const {
    nlohmann::json out = nlohmann::json::array();
    for (size_t n = 0; n < probes.size(); ++n) {
        const FeatureProbe& p = probes[n];
        nlohmann::json entry{{"name", p.name},
                             {"kind", p.gap ? "gap" : "solid"},
                             {"objective_mm", p.objective},
                             {"simulated_mm", simulated[n]},
                             {"simulated_minus_objective_mm", simulated[n] - p.objective}};
        if (!p.measured.empty()) {
            double mean = 0;
            for (double m : p.measured) mean += m;
            mean /= double(p.measured.size());
            entry["measured_mm"] = p.measured;
            entry["simulated_minus_measured_mm"] = simulated[n] - mean;
        }
        out.push_back(entry);
    }
    return out;
}

}  // namespace vpsim::validate
