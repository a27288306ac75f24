#include "vpsim/validate/feature_probe.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

namespace vpsim::validate {

FeatureProbes::FeatureProbes(std::vector<FeatureProbe> probes, const exposure::ExposureGrid& grid,
                             double criticalDose, double voxelHeight)
    : mProbes(std::move(probes)),
      mGrid(grid),
      mCriticalDose(criticalDose),
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
        bool cured = slice.values->at(i, j) >= mCriticalDose;
        if (cured != p.gap) mLength[n] += mVoxelHeight;
    }
}

nlohmann::json FeatureProbes::toJson() const {
    nlohmann::json out = nlohmann::json::array();
    for (size_t n = 0; n < mProbes.size(); ++n) {
        const FeatureProbe& p = mProbes[n];
        nlohmann::json entry{{"name", p.name},
                             {"kind", p.gap ? "gap" : "solid"},
                             {"objective_mm", p.objective},
                             {"simulated_mm", mLength[n]},
                             {"simulated_minus_objective_mm", mLength[n] - p.objective}};
        if (!p.measured.empty()) {
            double mean = 0;
            for (double m : p.measured) mean += m;
            mean /= double(p.measured.size());
            entry["measured_mm"] = p.measured;
            entry["simulated_minus_measured_mm"] = mLength[n] - mean;
        }
        out.push_back(entry);
    }
    return out;
}

}  // namespace vpsim::validate
