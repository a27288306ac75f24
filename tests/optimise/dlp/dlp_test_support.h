#pragma once
// Shared by the DLP optimiser tests: the seed 001 resin (Table 1) as a column problem.

#include "vpsim/optimise/dlp/column.h"

namespace vpsim::test {

/// Seed 001's resin (K, Dp, Phi_c of Table 1) at 50 um layers, with d_max and the Eq. 10 reading.
inline optimise::DlpColumnProblem seedResin(
    double maxDose = 1.3, optimise::Bonding bonding = optimise::Bonding::OwnLayer) {
    optimise::DlpColumnProblem p;
    p.layerThickness = 0.05;
    p.rateConstant = 0.528080236;
    p.attenuation = 1.0 / 0.365935872;
    p.gelPoint = 0.276;
    p.maxDose = maxDose;
    p.bonding = bonding;
    return p;
}

}  // namespace vpsim::test
