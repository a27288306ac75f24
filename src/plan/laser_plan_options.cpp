#include "vpsim/plan/laser_plan_options.h"

#include <algorithm>

#include "vpsim/plan/scan_report.h"

namespace vpsim::plan {

LaserPlanOptions readLaserPlanOptions(const ConfigNode& plan) {
    LaserPlanOptions options;
    readAcesKeys(plan, options.aces);
    options.direction = directionRuleFromConfig(plan);
    options.order = orderMethodFromConfig(plan);
    return options;
}

std::vector<ConfigKeyDoc> laserPlanKeys() {
    return {{"homogeneity",
             "ACES Srlt: allowed relative standard deviation of the exposure (default 0.01)"},
            {"edge",
             "seed-5-percent (default: the 5% Ep edge on the contour, seed 000 App. A) "
             "| cure-at-contour (the cured wall on the contour on average over the layer depth)"},
            {"border_count", "border (contour) scan loops (default 1)"},
            {"border_offset", "inward offset of the first border loop (default: the edge rule's)"},
            {"direction",
             "scan direction of each layer: min-edge-projection (default, seed 002 Sec. 3) | "
             "longest-edge | a fixed angle such as \"0 deg\""},
            {"order",
             "order of each layer's parts by jump time: auto (default: exact up to 16 parts, "
             "heuristic beyond) | exact | heuristic | nearest-neighbour | as-sliced"}};
}

AcesParameters acesParameters(const LaserPlanOptions& options, const kernel::FittedBeam& beam,
                              const Machine& machine, double criticalDose) {
    AcesParameters aces = options.aces;
    aces.beamRadius = beam.radius;
    aces.attenuationLength = beam.attenuationLength;
    aces.depthOfMaximum = std::min(beam.depthOfMaximum, 0.99 * machine.layerThickness);
    aces.criticalDose = criticalDose / beam.efficiency;
    aces.layerThickness = machine.layerThickness;
    aces.laserPower = machine.laserPower;
    return aces;
}

}  // namespace vpsim::plan
