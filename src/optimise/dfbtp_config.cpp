#include "vpsim/optimise/dfbtp_config.h"

#include <algorithm>

#include "vpsim/core/config.h"
#include "vpsim/core/units.h"

namespace vpsim::optimise {
namespace {

double pitch(const ConfigNode& plan, const std::string& key, double fallback) {
    double value = plan.quantity(key, dim::LENGTH, fallback);
    if (!(value >= 1e-4 && value <= 1.0)) throw plan.error(key, "must be between 0.1 um and 1 mm");
    return value;
}

}  // namespace

DfbtpParameters readDfbtpKeys(const ConfigNode& plan) {
    DfbtpParameters p;
    // The ACES keys are read so one job runs under every laser strategy; DFBTP's middle area
    // keeps the seed's 5% rule and no border loops (planDfbtp sets them), only homogeneity and
    // direction matter to it.
    plan::readAcesKeys(plan, p.aces);
    p.dotPitch = pitch(plan, "dot_pitch", p.dotPitch);
    p.gridPitch = pitch(plan, "grid_pitch", p.gridPitch);
    p.liftOutside = plan.numberInRange("lift_outside", 0.0, 10.0, p.liftOutside);
    p.liftEdge = plan.numberInRange("lift_edge", 0.0, 10.0, p.liftEdge);
    p.liftInside = plan.numberInRange("lift_inside", 0.0, 10.0, p.liftInside);
    p.compensate = plan.boolean("compensate", p.compensate);
    return p;
}

InverseParameters readInverseKeys(const ConfigNode& plan) {
    InverseParameters p;
    p.base.aces.edge = plan::AcesEdge::CureAtContour;
    plan::readAcesKeys(plan, p.base.aces);
    p.dotPitch = pitch(plan, "dot_pitch", p.dotPitch);
    p.base.gridPitch = pitch(plan, "grid_pitch", p.base.gridPitch);
    long long iterations = plan.integer("iterations", p.iterations);
    if (iterations < 0 || iterations > 100000)
        throw plan.error("iterations", "must be between 0 and 100000");
    p.iterations = int(iterations);
    long long coarse = plan.integer("coarse_iterations", p.coarseIterations);
    if (coarse < 0 || coarse > 100000)
        throw plan.error("coarse_iterations", "must be between 0 and 100000");
    p.coarseIterations = int(coarse);
    p.base.compensate = plan.boolean("compensate", p.base.compensate);
    return p;
}

std::vector<ConfigKeyDoc> dfbtpKeyDocs() {
    return {{"dot_pitch", "corner dot grid and edge row spacing (length, default 20 um)"},
            {"grid_pitch", "planning grid: exposure maps and evaluation points (length, 10 um)"},
            {"lift_outside", "a_i outside the part, fraction of Etar (default 0.15)"},
            {"lift_edge", "a_i in the under-exposed band inside the contour (default 0.25)"},
            {"lift_inside", "a_i inside the middle area (default 0.05)"},
            {"compensate", "subtract the exposure the layers above transmit (default true)"},
            {"border_count", "ACES border loops (accepted, unused by DFBTP)"},
            {"border_offset", "ACES first border loop offset (accepted, unused by DFBTP)"},
            {"direction", "hatch direction in degrees from +x (default: longest edge)"}};
}

std::vector<ConfigKeyDoc> inverseKeyDocs() {
    return {
        {"dot_pitch", "dot grid pitch, a whole number of grid cells (length, 20 um)"},
        {"grid_pitch", "planning grid (length, default 10 um)"},
        {"iterations", "projected-gradient iterations per layer (default 40)"},
        {"coarse_iterations", "iterations first on a grid at the dot pitch (default 80; 0: none)"},
        {"compensate", "subtract the exposure the layers above transmit (default true)"},
        {"border_count", "border loops of the ACES warm start (default 1)"},
        {"border_offset", "first border loop offset of the warm start (length)"},
        {"direction", "hatch direction of the warm start, degrees from +x"}};
}

void setProcess(plan::AcesParameters& aces, const kernel::FittedBeam& beam, double criticalDose,
                double layerThickness, double laserPower) {
    aces.beamRadius = beam.radius;
    aces.attenuationLength = beam.attenuationLength;
    aces.depthOfMaximum = std::min(beam.depthOfMaximum, 0.99 * layerThickness);
    aces.criticalDose = criticalDose / beam.efficiency;
    aces.layerThickness = layerThickness;
    aces.laserPower = laserPower;
}

}  // namespace vpsim::optimise
