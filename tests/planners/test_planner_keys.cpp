// The built-in planners read their plan section through their key tables: defaults, units,
// ranges and bad values, and the shared laser keys.
#include <catch2/catch.hpp>

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/planners/dfbtp_planner.h"
#include "vpsim/planners/inverse_planner.h"
#include "vpsim/planners/laser_plan_options.h"
#include "vpsim/planners/optimised_mask_planner.h"

using namespace vpsim;
using namespace vpsim::planners;
using Catch::Matchers::Contains;

namespace {

ConfigNode planSection(const std::string& text) {
    return ConfigNode(nlohmann::json::parse(text), "job.json").child("plan");
}

}  // namespace

TEST_CASE("laser keys: ACES parameters, direction and order", "[planners][keys]") {
    const KeyTable table = laserPlanKeyTable();
    ConfigNode section = planSection(R"({"plan": {"order": "heuristic", "direction": "15 deg",
        "homogeneity": 0.02, "border_count": 2, "border_offset": "5 um"}})");
    LaserPlanOptions o = readLaserPlanOptions(KeyReader(table, section, "planner 'aces'"));
    CHECK(o.order == plan::OrderMethod::Heuristic);
    CHECK(o.direction.angle == Approx(M_PI / 12));
    CHECK(o.aces.homogeneity == 0.02);
    CHECK(o.aces.borderCount == 2);
    CHECK(*o.aces.borderOffset == Approx(0.005));
    CHECK(o.aces.edge == plan::AcesEdge::SeedFivePercent);
    o = readLaserPlanOptions(KeyReader(table, planSection(R"({"plan": {}})"), "aces"));
    CHECK(o.order == plan::OrderMethod::Auto);
    CHECK(o.direction.kind == plan::DirectionRule::Kind::MinEdgeProjection);
    CHECK_FALSE(o.aces.borderOffset);
    CHECK_THROWS_WITH(
        readLaserPlanOptions(KeyReader(table, planSection(R"({"plan": {"order": "random"}})"), "")),
        Contains("order"));
    CHECK_THROWS_WITH(readLaserPlanOptions(
                          KeyReader(table, planSection(R"({"plan": {"border_count": -1}})"), "")),
                      Contains("border_count"));
    // The inverse planner's warm start defaults to the cure-at-contour edge.
    o = readLaserPlanOptions(KeyReader(inverseKeyTable(), planSection(R"({"plan": {}})"), ""));
    CHECK(o.aces.edge == plan::AcesEdge::CureAtContour);
}

TEST_CASE("dfbtp and inverse read their own keys", "[planners][keys]") {
    ConfigNode dfbtp = planSection(
        R"({"plan": {"dot_pitch": "25 um", "lift_outside": 0.1, "compensate": false}})");
    optimise::DfbtpParameters p = readDfbtpParameters(KeyReader(dfbtpKeyTable(), dfbtp, ""));
    CHECK(p.dotPitch == Approx(0.025));
    CHECK(p.gridPitch == Approx(0.01));
    CHECK(p.liftOutside == Approx(0.1));
    CHECK(p.liftEdge == Approx(0.25));
    CHECK_FALSE(p.compensate);
    optimise::InverseParameters ip = readInverseParameters(
        KeyReader(inverseKeyTable(), planSection(R"({"plan": {"iterations": 5}})"), ""));
    CHECK(ip.iterations == 5);
    CHECK(ip.coarseIterations == 40);
    CHECK_THROWS_AS(readDfbtpParameters(KeyReader(
                        dfbtpKeyTable(), planSection(R"({"plan": {"dot_pitch": "-1 um"}})"), "")),
                    InputError);
    CHECK_THROWS_AS(readInverseParameters(KeyReader(
                        inverseKeyTable(), planSection(R"({"plan": {"iterations": -1}})"), "")),
                    InputError);
}

TEST_CASE("optimised-mask: settings from the plan section", "[planners][keys]") {
    const KeyTable table = optimisedMaskKeyTable();
    auto read = [&](const std::string& text) {
        return readOptimisedMaskSettings(KeyReader(table, planSection(text), "optimised-mask"));
    };
    optimise::DlpMaskPlannerSettings s = read(R"({"plan": {"max_dose": "130 mJ/cm^2",
        "bonding": "run-bottom", "objective": "geometric"}})");
    REQUIRE(s.maxDose == Approx(1.3).epsilon(1e-12));
    REQUIRE(s.bonding == optimise::Bonding::RunBottom);
    REQUIRE(s.objective == optimise::DlpObjective::Geometric);
    REQUIRE(s.targetConversion == 0.95);
    REQUIRE(s.penalty == 5.5);
    REQUIRE(s.uniformDose == -1.0);  // "mean" by default
    REQUIRE(s.figureLayer == -1);
    REQUIRE_FALSE(s.figureColumnGiven);
    s = read(R"({"plan": {"uniform_dose": "78 mJ/cm^2", "figure_x": "3.5 mm", "figure_y": 0,
        "figure_layer": 12}})");
    REQUIRE(s.uniformDose == Approx(0.78).epsilon(1e-12));
    REQUIRE(s.figureColumnGiven);
    REQUIRE(s.figureX == Approx(3.5));
    REQUIRE(s.figureLayer == 12);
    REQUIRE_THROWS_WITH(read(R"({"plan": {"uniform_dose": "-1 mJ/cm^2"}})"),
                        Contains("uniform_dose"));
    REQUIRE_THROWS_WITH(read(R"({"plan": {"bonding": "glue"}})"), Contains("bonding"));
}
