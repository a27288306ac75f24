// The inverse planner against the shipped `aces` planner, both created through the planner
// registry from their key tables (as a job gets them), on the seed's exposure objective: the
// layer exposure error of seed 000 Section III-B (optimise/laser/exposure_error.h) against
// Etar = Ec exp((lt - zmax)/De3D) inside the part and 0 outside, over the part grown by Reff,
// on a 10 um grid, of each layer's total surface exposure (own + transmitted from above).
// Each plan's SSE is measured here from the returned plan alone (deposited and exposed through
// a fresh exposure engine), never taken from the planner's own report, and compared with the
// SSE of the plan `aces` returns with its stack-aware cure-at-contour rule (the edge rule the
// inverse planner's warm start uses) and with its default (seed 5%) rule.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpsim/cure/threshold_law.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/plan/feature_blocks.h"
#include "vpsim/planners/aces_planner.h"
#include "vpsim/planners/inverse_planner.h"

using namespace vpsim;

namespace {

/// The default job's L part (examples/default.json: l-shape, 2 mm, centred).
geometry::PolygonSet lShape() {
    return geometry::PolygonSet::rectangle({0, 0}, {2, 1})
        .unite(geometry::PolygonSet::rectangle({0, 1}, {1, 2}))
        .translated({-1, -1});
}

/// The default job's process: its fitted Monte Carlo kernel (We3D 63.2 um, De3D 36.7 um, zmax
/// 2.2 um, efficiency 2.37), Ec 10 mJ/cm^2, 10 mW, 50 um layers.
struct Process {
    kernel::FittedBeam beam{0.0632, 0.0367, 0.0022, 2.37};
    plan::Machine machine;
    double ec = 0.1;  // mJ/mm^2
    cure::ThresholdLaw law{0.1};
    Process() {
        machine.process = plan::Process::Laser;
        machine.layerThickness = 0.05;
        machine.laserPower = 10.0;
        machine.beamRadius = 0.05;
    }
    /// Etar by seed 000 Eq. 14, written out here (zmax below the layer thickness).
    double etar() const {
        return ec *
               std::exp((machine.layerThickness - beam.depthOfMaximum) / beam.attenuationLength);
    }
};

geometry::LayerStack stackOf(const geometry::PolygonSet& region, int layers) {
    geometry::LayerStack stack;
    stack.layerThickness = 0.05;
    for (int k = 0; k < layers; ++k)
        stack.layers.push_back({k, 0.05 * k, 0.05 * k + 0.025, region});
    return stack;
}

plan::ScanPlan planWith(const std::string& name, const nlohmann::json& section,
                        const geometry::LayerStack& stack, const Process& p) {
    planners::PlannerRegistry registry("planner");
    planners::registerAcesPlanner(registry);
    planners::registerInversePlanner(registry);
    std::unique_ptr<planners::Planner> planner =
        registry.create(name, ConfigNode(section, "test.json"));
    geometry::Bounds bounds;
    bounds.add({-1, -1, 0});
    bounds.add({1, 1, 0.05 * stack.layers.size()});
    const RunContext context{nullptr, false, ""};
    return planner->plan({stack, bounds, p.machine, p.beam, nullptr, p.ec, p.law, context});
}

/// The plan's total SSE over its layers (mJ^2/mm^4), measured from the plan alone.
double sseOf(const plan::ScanPlan& plan, const geometry::LayerStack& stack, const Process& p) {
    std::vector<geometry::PolygonSet> regions;
    for (const auto& layer : stack.layers) regions.push_back(layer.region);
    exposure::ExposureEngine engine(optimise::planningGrid(regions, p.beam.radius, 0.01), p.beam,
                                    p.machine.layerThickness);
    const nlohmann::json e = optimise::planExposureError(engine, plan, regions, p.etar(),
                                                         plan::effectiveRadius(p.beam.radius));
    return e["sse_mJ2_per_mm4"].get<double>();
}

/// The inverse planner's section: its defaults but for `edge`, with the exposure objective
/// pinned (`plan.objective` defaults to the 3D shape objective since issue 23): the seed's
/// exposure error (inverse.h), whose target wall lies on the contour under the cure-at-contour
/// edge (its default) and on the model's edge under the seed's 5% edge (then it is exactly the
/// metric measured here).
nlohmann::json inverseSection(const std::string& edge) {
    nlohmann::json section = {{"objective", "exposure-l2"}};
    if (!edge.empty()) section["edge"] = edge;
    return section;
}

}  // namespace

// On one layer (seed 000 Fig. 22's setting) and on a stack of three, where the stack-aware
// contour rule of `aces` and the top-down compensation of the inverse planner both see the
// layers above. Measured (SSE mJ^2/mm^4, 1 layer / 3 layers): aces cure-at-contour 66.8 / 778,
// aces default (5% edge) 318 / 1391; inverse as shipped (cure-at-contour warm start, target
// wall on the contour) 65.3 / 196, i.e. 0.977 / 0.251 of aces cure-at-contour; inverse with the
// 5% edge (the objective is then exactly this metric) 56.8 / 170, i.e. 0.85 / 0.22.
// The plans are deterministic and the maps' float error is about 1e-6 relative, so the bounds
// (0.99 for the shipped inverse on one layer, 0.9 elsewhere) sit above the measurements by
// 1.3-40% and below 1: an inverse plan no better than the shipped ACES fails.
TEST_CASE("the inverse plan's exposure error is below the shipped ACES plan's", "[planners]") {
    const Process p;
    for (int layers : {1, 3}) {
        const geometry::LayerStack stack = stackOf(lShape(), layers);
        const double acesContour =
            sseOf(planWith("aces", {{"edge", "cure-at-contour"}}, stack, p), stack, p);
        const double acesDefault =
            sseOf(planWith("aces", nlohmann::json::object(), stack, p), stack, p);
        const double shipped = sseOf(planWith("inverse", inverseSection(""), stack, p), stack, p);
        const double exact =
            sseOf(planWith("inverse", inverseSection("seed-5-percent"), stack, p), stack, p);
        INFO(layers << " layer(s), SSE mJ^2/mm^4: aces cure-at-contour " << acesContour
                    << ", aces default " << acesDefault << "; inverse as shipped " << shipped
                    << " (" << shipped / acesContour << " of aces cure-at-contour), inverse with "
                    << "the 5% edge " << exact << " (" << exact / acesContour << ")");
        CHECK(shipped < (layers == 1 ? 0.99 : 0.9) * acesContour);
        CHECK(exact < 0.9 * acesContour);
        CHECK(shipped < 0.9 * acesDefault);
        CHECK(exact < 0.9 * acesDefault);
    }
}
