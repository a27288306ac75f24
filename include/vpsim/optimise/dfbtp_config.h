#pragma once
/// @file
/// The job keys of the `dfbtp` and `inverse` strategies (a job's `plan` section), and the beam
/// and process numbers every laser planner shares.
///
/// dfbtp:   the ACES keys (plan::readAcesKeys; edge and border keys are accepted and ignored:
///          the middle area uses the seed's 5% rule), dot_pitch (length, 20 um), grid_pitch
///          (length, 10 um), lift_outside (0.15), lift_edge (0.25), lift_inside (0.05), compensate
///          (true)
/// inverse: homogeneity, edge, border_count, border_offset (its ACES warm start), dot_pitch
///          (20 um), grid_pitch (10 um), iterations (40), compensate (true)

#include <vector>

#include "vpsim/core/registry.h"
#include "vpsim/optimise/inverse_planner.h"

namespace vpsim {
class ConfigNode;
}

namespace vpsim::optimise {

/// @throw InputError naming the key for bad values
DfbtpParameters readDfbtpKeys(const ConfigNode& plan);
/// @throw InputError naming the key for bad values
InverseParameters readInverseKeys(const ConfigNode& plan);

/// The keys readDfbtpKeys() and readInverseKeys() read beyond the shared laser keys (homogeneity,
/// edge), for `vpsim plan --list`.
std::vector<ConfigKeyDoc> dfbtpKeyDocs();
std::vector<ConfigKeyDoc> inverseKeyDocs();

/// Beam and process of an ACES design from the fitted beam (zmax capped below the layer) and
/// the cure law's critical dose `criticalDose` (mJ/mm^2, divided by the beam efficiency: Etar is
/// asked of the delivered dose).
void setProcess(plan::AcesParameters& aces, const kernel::FittedBeam& beam, double criticalDose,
                double layerThickness, double laserPower);

}  // namespace vpsim::optimise
