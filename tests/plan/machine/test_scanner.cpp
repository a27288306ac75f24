// Jump kinematics against hand-derived closed forms (seed 002 Section 4, Fig. 6), with the seed's
// limits: machine 2 m/s and 20 m/s^2 = 2000 mm/s and 20000 mm/s^2.
#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/plan/machine/scanner.h"

using namespace vpsim;
using namespace vpsim::plan;

namespace {
const AxisLimits MACHINE{2000.0, 20000.0};
}

TEST_CASE("rest-to-rest moves are triangular up to v^2/a and trapezoidal beyond", "[plan]") {
    // 1 mm: peak sqrt(a d) = 141 mm/s < 2000, t = 2 sqrt(d / a).
    CHECK(restToRestTime(1.0, MACHINE) == Approx(2.0 * std::sqrt(1.0 / 20000.0)));
    // 500 mm > v^2/a = 200 mm: 0.1 s each to accelerate and brake (100 mm each), 300 mm at
    // 2000 mm/s.
    CHECK(restToRestTime(500.0, MACHINE) == Approx(0.2 + 300.0 / 2000.0));
    // At d = v^2/a both forms agree (0.2 s).
    CHECK(restToRestTime(200.0, MACHINE) == Approx(0.2));
    CHECK(axisMoveTime(-500.0, 0.0, MACHINE) == Approx(0.25 + 0.1));
}

TEST_CASE("a jump starting with the mark velocity keeps going, overshoots or reverses", "[plan]") {
    const double v0 = 300.0;  // the seed's process speed, 0.3 m/s; braking distance 2.25 mm
    SECTION("target exactly at the braking distance: brake only") {
        CHECK(axisMoveTime(2.25, v0, MACHINE) == Approx(0.015));
    }
    SECTION("keep going, triangular: peak^2 = a d + v0^2/2") {
        // 10 mm: peak sqrt(245000) = 494.97 mm/s; accelerate 3.875 mm, brake 6.125 mm.
        const double vp = std::sqrt(245000.0);
        CHECK(axisMoveTime(10.0, v0, MACHINE) == Approx((vp - v0) / 20000.0 + vp / 20000.0));
        CHECK((vp * vp - v0 * v0) / 40000.0 + vp * vp / 40000.0 == Approx(10.0));
    }
    SECTION("keep going, trapezoidal") {
        // 500 mm: accelerate 300 -> 2000 (0.085 s, 97.75 mm), brake 0.1 s (100 mm), cruise
        // 302.25 mm.
        CHECK(axisMoveTime(500.0, v0, MACHINE) == Approx(0.085 + 0.1 + 302.25 / 2000.0));
    }
    SECTION("overshoot (seed 002 Fig. 6 scenario 1): brake past the target, come back") {
        // 1 mm ahead: brake 0.015 s to 2.25 mm, then 1.25 mm back from rest to rest.
        CHECK(axisMoveTime(1.0, v0, MACHINE) == Approx(0.015 + 2.0 * std::sqrt(1.25 / 20000.0)));
    }
    SECTION("reversal (scenario 3): brake, then move the other way") {
        // 10 mm behind: brake 0.015 s (2.25 mm further), then 12.25 mm rest to rest.
        CHECK(axisMoveTime(-10.0, v0, MACHINE) == Approx(0.015 + 2.0 * std::sqrt(12.25 / 20000.0)));
        CHECK(axisMoveTime(10.0, -v0, MACHINE) == Approx(axisMoveTime(-10.0, v0, MACHINE)));
    }
    SECTION("an axis at rest on its target with a velocity still has to stop and return") {
        CHECK(axisMoveTime(0.0, v0, MACHINE) == Approx(0.015 + 2.0 * std::sqrt(2.25 / 20000.0)));
    }
}

TEST_CASE("a move takes as long as its slower axis", "[plan]") {
    // x: 3 mm from rest (0.0245 s); y: moving at 300 mm/s, target 0 => stop and return (0.0362).
    const double tx = 2.0 * std::sqrt(3.0 / 20000.0);
    const double ty = 0.015 + 2.0 * std::sqrt(2.25 / 20000.0);
    CHECK(jumpTime({0, 0}, {3, 0}, {0, 300}, MACHINE) == Approx(std::max(tx, ty)));
    CHECK(jumpTime({0, 0}, {500, 1}, {0, 0}, MACHINE) == Approx(0.35));
    // Per-axis limits: a diagonal is not slower than its longer axis alone.
    CHECK(jumpTime({0, 0}, {4, 4}, {0, 0}, MACHINE) == Approx(restToRestTime(4, MACHINE)));
}

TEST_CASE("machine.scanner parses units, defaults and rejects bad values", "[plan]") {
    ConfigNode node(nlohmann::json{{"machine_speed", "2 m/s"},
                                   {"machine_acceleration", "20 m/s^2"},
                                   {"process_speed", "0.6 m/s"},
                                   {"delays", {{"jump", "300 us"}, {"polygon", "0 s"}}}},
                    "machine.json");
    ScannerConfig config = scannerFromConfig(node);
    node.checkUnknownKeys();
    CHECK(config.machine.speed == Approx(2000.0));
    CHECK(config.machine.acceleration == Approx(20000.0));
    CHECK(config.process.speed == Approx(600.0));
    CHECK(config.process.acceleration == Approx(2000.0));  // seed 002 default
    CHECK(config.delays.jump == Approx(300e-6));
    CHECK(config.delays.mark == Approx(100e-6));  // Table 1
    CHECK(config.delays.polygon == 0.0);

    ConfigNode tooFast(nlohmann::json{{"process_speed", "3 m/s"}}, "machine.json");
    CHECK_THROWS_AS(scannerFromConfig(tooFast), InputError);
    ConfigNode negative(nlohmann::json{{"delays", {{"mark", "-1 us"}}}}, "machine.json");
    CHECK_THROWS_WITH(scannerFromConfig(negative), Catch::Contains("mark"));
    ConfigNode wrongUnit(nlohmann::json{{"machine_speed", "2 m"}}, "machine.json");
    CHECK_THROWS_AS(scannerFromConfig(wrongUnit), InputError);
}
