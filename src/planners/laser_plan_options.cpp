#include "vpsim/planners/laser_plan_options.h"

#include <algorithm>
#include <cmath>

#include "vpsim/plan/machine/laser_limits.h"

namespace vpsim::planners {
namespace {

const char* edgeName(plan::AcesEdge edge) {
    return edge == plan::AcesEdge::SeedFivePercent ? "seed-5-percent" : "cure-at-contour";
}

}  // namespace

KeyTable laserPlanKeyTable(plan::AcesEdge edgeDefault) {
    return {{
        numberKey("homogeneity", 0.01,
                  "ACES Srlt: allowed relative standard deviation of the exposure")
            .in(1e-6, 0.5),
        choiceKey("edge", {"seed-5-percent", "cure-at-contour"}, edgeName(edgeDefault),
                  "seed-5-percent: the 5% Ep edge on the contour (seed 000 App. A); "
                  "cure-at-contour: the cured wall on the contour on average over the layer "
                  "depth"),
        integerKey("border_count", 1, "border (contour) scan loops").in(0, 100),
        quantityKey("border_offset", dim::LENGTH, nullptr,
                    "inward offset of the first border loop (default: the edge rule's)")
            .in(0, INFINITY),
        stringKey("direction", "min-edge-projection",
                  "scan direction of each layer: min-edge-projection (seed 002 Sec. 3) | "
                  "longest-edge | a fixed angle such as \"0 deg\""),
        stringKey("order", "auto",
                  "order of each layer's parts by jump time: auto (exact up to 16 parts, "
                  "heuristic beyond) | exact | heuristic | nearest-neighbour | as-sliced"),
    }};
}

LaserPlanOptions readLaserPlanOptions(const KeyReader& keys) {
    LaserPlanOptions options;
    plan::AcesParameters& aces = options.aces;
    aces.homogeneity = keys.number("homogeneity");
    aces.edge = keys.choice("edge") == "seed-5-percent" ? plan::AcesEdge::SeedFivePercent
                                                        : plan::AcesEdge::CureAtContour;
    aces.borderCount = int(keys.integer("border_count"));
    aces.borderOffset = keys.optionalQuantity("border_offset");
    const ConfigNode& node = keys.node();
    options.direction =
        plan::parseDirectionRule(keys.string("direction"), node.keyPath("direction"), node.file());
    options.order =
        plan::parseOrderMethod(keys.string("order"), node.keyPath("order"), node.file());
    return options;
}

plan::AcesParameters acesParameters(const LaserPlanOptions& options, const kernel::FittedBeam& beam,
                                    const plan::Machine& machine, double criticalDose) {
    plan::AcesParameters aces = options.aces;
    aces.beamRadius = beam.radius;
    aces.attenuationLength = beam.attenuationLength;
    aces.depthOfMaximum = std::min(beam.depthOfMaximum, 0.99 * machine.layerThickness);
    aces.criticalDose = criticalDose / beam.efficiency;
    aces.layerThickness = machine.layerThickness;
    aces.laserPower = machine.laserPower;
    return aces;
}

void checkLaserDose(const plan::AcesParameters& aces, const plan::Machine& machine) {
    const double target = plan::acesTargetDose(aces.criticalDose, aces.layerThickness,
                                               aces.depthOfMaximum, aces.attenuationLength);
    plan::checkDoseReachable(machine, target,
                             plan::acesHatchRatio(aces.homogeneity) * aces.beamRadius);
}

nlohmann::json fitLaserPlan(plan::ScanPlan& plan, const plan::AcesParameters& aces,
                            const plan::Machine& machine, double dotPitch) {
    const plan::LaserLimits limits =
        plan::laserLimits(machine, aces.beamRadius, NEGLIGIBLE_FRACTION_OF_EC * aces.criticalDose);
    return {{"laser", plan::fitPlanToLimits(plan, limits, dotPitch).toJson()}};
}

}  // namespace vpsim::planners
