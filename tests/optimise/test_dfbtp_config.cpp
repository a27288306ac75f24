#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/optimise/dfbtp_config.h"
#include "vpsim/optimise/dfbtp_planner.h"

using namespace vpsim;

namespace {
ConfigNode planSection(const std::string& text) {
    return ConfigNode(nlohmann::json::parse(text), "job.json").child("plan");
}
}  // namespace

TEST_CASE("DFBTP and inverse read their job keys", "[optimise][dfbtp]") {
    auto plan = planSection(
        R"({"plan": {"strategy": "dfbtp", "dot_pitch": "25 um", "lift_outside": 0.1,
                     "compensate": false, "homogeneity": 0.02}})");
    plan.string("strategy");
    auto p = optimise::readDfbtpKeys(plan);
    plan.checkUnknownKeys();
    CHECK(p.dotPitch == Approx(0.025));
    CHECK(p.liftOutside == Approx(0.1));
    CHECK_FALSE(p.compensate);
    CHECK(p.aces.homogeneity == Approx(0.02));

    auto inv =
        planSection(R"({"plan": {"iterations": 5, "border_count": 2, "edge": "seed-5-percent"}})");
    auto ip = optimise::readInverseKeys(inv);
    inv.checkUnknownKeys();
    CHECK(ip.iterations == 5);
    CHECK(ip.base.aces.borderCount == 2);
    CHECK(ip.base.aces.edge == plan::AcesEdge::SeedFivePercent);
    CHECK(optimise::readInverseKeys(planSection(R"({"plan": {}})")).base.aces.edge ==
          plan::AcesEdge::CureAtContour);

    CHECK_THROWS_AS(optimise::readDfbtpKeys(planSection(R"({"plan": {"dot_pitch": "-1 um"}})")),
                    InputError);
    CHECK_THROWS_AS(optimise::readInverseKeys(planSection(R"({"plan": {"border_count": -1}})")),
                    InputError);
    auto unknown = planSection(R"({"plan": {"dot_pitchh": "20 um"}})");
    optimise::readDfbtpKeys(unknown);
    CHECK_THROWS_AS(unknown.checkUnknownKeys(), InputError);

    kernel::FittedBeam beam{0.06, 0.04, 0.08, 2.0};
    plan::AcesParameters a;
    optimise::setProcess(a, beam, 0.1, 0.05, 10.0);
    CHECK(a.depthOfMaximum == Approx(0.0495));  // capped below the layer thickness
    CHECK(a.criticalDose == Approx(0.05));
}

// The target growth for the cured wall: none when the wall level is half the plateau at every
// depth (the blurred step's half point is the contour); outward when the wall level is higher.
TEST_CASE("the target wall shift follows the wall level", "[optimise][dfbtp]") {
    plan::AcesParameters a;
    a.beamRadius = 0.05;
    a.layerThickness = 1e-7;  // no depth: the wall level is Ec / Etar throughout
    a.attenuationLength = 0.1;
    a.criticalDose = 0.5;
    CHECK(optimise::targetWallShift(a, 1.0) == Approx(0.0).margin(2e-4));
    a.criticalDose = 0.7;  // 0.5 erfc(sqrt(2) u / W) = 0.7 at u = -0.2622 W: grow by 0.2622 W
    CHECK(optimise::targetWallShift(a, 1.0) == Approx(0.2622 * 0.05).epsilon(0.02));
}
