#pragma once
/// @file
/// Z dimensions of named features, measured like a caliper on the printed part: along a vertical
/// line at (x, y) within [zMin, zMax], the total cured length ("solid": an overhang's thickness)
/// or uncured length ("gap": a hole's height). Seed 001 Table 2 reports these for its case parts.

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/cure/cure_law.h"
#include "vpsim/exposure/exposure_model.h"

namespace vpsim {
class ConfigNode;
}

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
/// Reads a job's `features` list: [{"name", "x", "y", "z_min", "z_max", "kind": "gap" | "solid",
/// "objective", "measured": [mm, ...]}]. @throw InputError naming the file and key
std::vector<FeatureProbe> featureProbesFromConfig(const std::vector<ConfigNode>& entries);

/// The probes with the length each measured (mm).
struct FeatureMeasurements {
    std::vector<FeatureProbe> probes;
    std::vector<double> simulated;  ///< mm, per probe
    /// [{"name", "kind", "objective_mm", "simulated_mm", "simulated_minus_objective_mm",
    ///   "measured_mm"?, "simulated_minus_measured_mm"?}]
    nlohmann::json toJson() const;
};

class FeatureProbes {
public:
    /// @throw InputError when a probe lies outside the grid or has zMax <= zMin
    FeatureProbes(std::vector<FeatureProbe> probes, const exposure::ExposureGrid& grid,
                  const cure::CureLaw& law, double voxelHeight);
    void add(const exposure::ExposureSlice& slice);
    /// Simulated length of probe i (mm).
    double simulated(size_t i) const { return mLength[i]; }
    /// [{name, objective_mm, simulated_mm, measured_mm, simulated_minus_measured_mm}, ...]
    FeatureMeasurements result() const { return {mProbes, mLength}; }
    /// The lengths so far (for a checkpoint between tiles), and back.
    std::vector<double> saveState() const { return mLength; }
    /// @throw InputError when `lengths` is not one per probe
    void restoreState(const std::vector<double>& lengths);
    /// Adds the lengths another instance measured in other tiles (a probe's cell is in one).
    void mergeState(const std::vector<double>& lengths);

private:
    std::vector<FeatureProbe> mProbes;
    exposure::ExposureGrid mGrid;
    const cure::CureLaw* mLaw;
    double mVoxelHeight;
    std::vector<double> mLength;
};

}  // namespace vpsim::validate
