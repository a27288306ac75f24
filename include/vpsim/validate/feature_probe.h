#pragma once
/// @file
/// Z dimensions of named features, measured like a caliper on the printed part: along a vertical
/// line at (x, y) within [zMin, zMax], the total cured length ("solid": an overhang's thickness)
/// or uncured length ("gap": a hole's height). Seed 001 Table 2 reports these for its case parts.

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/exposure/exposure_engine.h"

namespace vpsim::validate {

struct FeatureProbe {
    std::string name;
    double x = 0, y = 0;           ///< mm, the measuring line
    double zMin = 0, zMax = 0;     ///< mm, the measured span
    bool gap = false;              ///< measure uncured (true) or cured (false) length
    double objective = 0;          ///< mm, the model's value
    std::vector<double> measured;  ///< mm, measurements of printed parts, if any
};

/// A SliceSink measuring every probe; slices may come in any order.
class FeatureProbes {
public:
    /// @throw InputError when a probe lies outside the grid or has zMax <= zMin
    FeatureProbes(std::vector<FeatureProbe> probes, const exposure::ExposureGrid& grid,
                  double criticalDose, double voxelHeight);
    void add(const exposure::ExposureSlice& slice);
    /// Simulated length of probe i (mm).
    double simulated(size_t i) const { return mLength[i]; }
    /// [{name, objective_mm, simulated_mm, measured_mm, simulated_minus_measured_mm}, ...]
    nlohmann::json toJson() const;

private:
    std::vector<FeatureProbe> mProbes;
    exposure::ExposureGrid mGrid;
    double mCriticalDose, mVoxelHeight;
    std::vector<double> mLength;
};

}  // namespace vpsim::validate
