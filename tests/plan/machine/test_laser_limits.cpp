// Laser plans within the machine's limits (issue 23 item 1): power range, process speed,
// negligible vectors and dots dropped, dot rows modulated along vectors, refusal before planning.
#include <catch2/catch.hpp>

#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/plan/machine/build_time.h"
#include "vpsim/plan/machine/laser_limits.h"
#include "vpsim/plan/machine/trajectory.h"

using namespace vpsim;
using namespace vpsim::plan;

namespace {

LaserLimits limits(double powerMin = 0) {
    LaserLimits l;
    l.powerMin = powerMin, l.powerMax = 10, l.processSpeed = 300, l.beamRadius = 0.05;
    l.negligibleDose = 0.001;  // mJ/mm^2: 1% of a 10 mJ/cm^2 critical dose
    return l;
}

double lineEnergy(const LaserVector& v) {
    return v.power / v.speed;
}

double energyOf(const LayerPlan& layer) {
    double sum = 0;
    for (const auto& v : layer.vectors) sum += lineEnergy(v) * std::hypot(v.x1 - v.x0, v.y1 - v.y0);
    for (const auto& p : layer.points) sum += p.energy;
    return sum;
}

}  // namespace

TEST_CASE("vectors run at the process speed with the power that keeps their dose", "[plan]") {
    ScanPlan plan;
    plan.machine.laserPower = 10;
    LayerPlan layer;
    layer.vectors = {{0, 0, 1, 0, 10, 1700},      // ACES today: 10 mW at 1.7 m/s
                     {0, 0.1, 1, 1.1, 10, 1700},  // diagonal: the axes allow sqrt(2) x 300 mm/s
                     {0, 0.2, 1, 0.2, 10, 20},  // dense: full power, slower than the process speed
                     {0, 0.3, 1, 0.3, 10, 3.2e6}};  // DFBTP's near-zero dose: negligible
    plan.layers = {layer};
    const LimitFit fit = fitPlanToLimits(plan, limits());
    const auto& out = plan.layers[0].vectors;
    REQUIRE(out.size() == 3);
    CHECK(fit.droppedNegligible == 1);
    CHECK(out[0].speed == Approx(300));
    CHECK(out[0].power == Approx(10.0 * 300 / 1700));
    CHECK(out[1].speed == Approx(300 * std::sqrt(2.0)));
    CHECK(out[2].power == Approx(10));
    CHECK(out[2].speed == Approx(20));
    for (size_t k = 0; k < 3; ++k)
        CHECK(lineEnergy(out[k]) == Approx(lineEnergy(layer.vectors[k])));
    const nlohmann::json use = laserUseJson(plan, 0, 300);
    CHECK(use["marks_above_process_speed"] == 0);
    CHECK(use["marks_above_max_power"] == 0);
    CHECK(use["speed_mm_per_s"][1].get<double>() == Approx(300 * std::sqrt(2.0)));
    // The build-time model agrees: no mark's axis speed above the process speed.
    CHECK(estimateBuildTime(plan, {}).sum.marksAboveProcessSpeed == 0);
}

TEST_CASE("a minimum power raises weak vectors or drops them", "[plan]") {
    ScanPlan plan;
    plan.machine.laserPower = 10;
    LayerPlan layer;
    // At 300 mm/s these need 3, 0.9 and 0.3 mW.
    layer.vectors = {{0, 0, 1, 0, 3, 300}, {0, 1, 1, 1, 0.9, 300}, {0, 2, 1, 2, 0.3, 300}};
    plan.layers = {layer};
    const LimitFit fit = fitPlanToLimits(plan, limits(1.0));
    const auto& out = plan.layers[0].vectors;
    REQUIRE(out.size() == 2);
    CHECK(out[0].power == Approx(3));
    CHECK(out[1].power == Approx(1.0));  // raised to the minimum
    CHECK(fit.raisedToMinPower == 1);
    CHECK(fit.droppedBelowMinPower == 1);
    const nlohmann::json use = laserUseJson(plan, 1.0, 300);
    CHECK(use["marks_below_min_power"] == 0);
    CHECK(use["power_mW"][0].get<double>() >= 1.0);
    CHECK(use["power_mW"][1].get<double>() <= 10.0);
}

TEST_CASE("dot rows become vectors modulated by power at one speed", "[plan]") {
    ScanPlan plan;
    plan.machine.laserPower = 10;
    LayerPlan layer;
    const double pitch = 0.02;
    // Two rows of 5 dots (the second with a hot dot), a lone dot, and a negligible dot.
    for (int i = 0; i < 5; ++i) layer.points.push_back({i * pitch, 0, 1e-4 * (1 + i)});
    for (int i = 0; i < 5; ++i) layer.points.push_back({i * pitch, pitch, i == 2 ? 1e-3 : 1e-4});
    layer.points.push_back({1, 1, 2e-4});
    layer.points.push_back({2, 2, 1e-9});
    plan.layers = {layer};
    const double before = energyOf(layer) - 1e-9;
    const LimitFit fit = fitPlanToLimits(plan, limits(), pitch);
    const LayerPlan& out = plan.layers[0];
    CHECK(fit.droppedNegligible == 1);
    CHECK(fit.pointsAsVectors == 10);
    CHECK(fit.dwellPoints == 1);
    REQUIRE(out.vectors.size() == 10);
    REQUIRE(out.points.size() == 1);
    CHECK(energyOf(out) == Approx(before));
    // Row one at the process speed; row two slower, so its hot dot gets 1e-3 mJ at 10 mW.
    for (int k = 0; k < 5; ++k) CHECK(out.vectors[size_t(k)].speed == Approx(300));
    for (int k = 5; k < 10; ++k) {
        CHECK(out.vectors[size_t(k)].speed == Approx(10 * pitch / 1e-3));
        CHECK(out.vectors[size_t(k)].power <= 10 + 1e-9);
    }
    // Serpentine: the second row runs backwards, and each row is one chain (no jumps inside).
    CHECK(out.vectors[5].x1 < out.vectors[5].x0);
    const LayerTrajectory t = buildLayerTrajectory(out, 10, {});
    const LayerTime time = layerMoveTime(t.moves, {});
    CHECK(time.polygonDelays == 0);  // collinear pieces at one speed: one vector, power changes
    CHECK(time.marksAboveProcessSpeed == 0);
}

TEST_CASE("a target dose the machine cannot deliver is refused with what to change", "[plan]") {
    Machine machine;
    machine.laserPower = 10, machine.laserPowerMin = 5;
    // 0.1 mJ/mm^2 on lines 50 um apart at 300 mm/s needs 1.5 mW, below the 5 mW minimum.
    try {
        checkDoseReachable(machine, 0.1, 0.05);
        FAIL("not refused");
    } catch (const InputError& e) {
        const std::string message = e.what();
        CHECK(message.find('\n') == std::string::npos);
        CHECK(message.find("machine.laser_power_min") != std::string::npos);
        CHECK(message.find("1.5 mW") != std::string::npos);
        CHECK(message.find("process_speed") != std::string::npos);
    }
    machine.laserPowerMin = 1.0;
    CHECK_NOTHROW(checkDoseReachable(machine, 0.1, 0.05));
}

TEST_CASE("a scan path runs at the speed that minimises its build time", "[plan]") {
    // A serpentine field of 2 mm lines, 50 um apart, at 0.02 mJ/mm (0.6 mW at 30 mm/s): brute
    // force over one common speed for all lines, through the build-time model, against the fit.
    const int lines = 20;
    ScanPlan field;
    field.machine.laserPower = 10;
    LayerPlan layer;
    for (int k = 0; k < lines; ++k) {
        const double y = 0.05 * k, x0 = k % 2 ? 2.0 : 0.0;
        layer.vectors.push_back({x0, y, 2.0 - x0, y, 0.6, 30.0});
    }
    field.layers = {layer};
    const BuildTimeOptions options;
    auto timeAt = [&](double speed) {
        ScanPlan trial = field;
        for (LaserVector& v : trial.layers[0].vectors) v.power *= speed / v.speed, v.speed = speed;
        return estimateBuildTime(trial, options).total();
    };
    double best = INFINITY;
    for (double speed = 10; speed <= 300; speed += 1) best = std::min(best, timeAt(speed));
    LaserLimits l = limits();
    l.jumpAcceleration = options.scanner.machine.acceleration;
    ScanPlan fitted = field;
    fitPlanToLimits(fitted, l);
    const double time = estimateBuildTime(fitted, options).total();
    INFO("fitted " << time << " s, best common speed " << best << " s, at the process speed "
                   << timeAt(300) << " s");
    CHECK(time <= best * 1.01);
    CHECK(time < 0.8 * timeAt(300));  // the reversals at 300 mm/s cost more than the marks
    for (size_t k = 0; k < fitted.layers[0].vectors.size(); ++k)
        CHECK(lineEnergy(fitted.layers[0].vectors[k]) == Approx(0.02));
    // Each line is its own path (they do not chain): sqrt(a L / 2).
    CHECK(fitted.layers[0].vectors[0].speed == Approx(std::sqrt(0.5 * 20000.0 * 2.0)));
}

TEST_CASE("a dot row with a gap is one scan path; negligible dots inside it are kept", "[plan]") {
    ScanPlan plan;
    plan.machine.laserPower = 10;
    LayerPlan layer;
    const double pitch = 0.02;
    // 30 dots along x with dots 10 and 11 missing and dot 20 negligible.
    for (int i = 0; i < 30; ++i)
        if (i != 10 && i != 11) layer.points.push_back({i * pitch, 0, i == 20 ? 1e-12 : 2e-4});
    plan.layers = {layer};
    LaserLimits l = limits();
    l.jumpAcceleration = 20000;
    const LimitFit fit = fitPlanToLimits(plan, l, pitch);
    const auto& out = plan.layers[0].vectors;
    CHECK(fit.droppedNegligible == 0);
    REQUIRE(out.size() == 28);
    // One path of 30 pitches (the gap included): one speed sqrt(a L / 2) for both runs.
    for (const LaserVector& v : out) CHECK(v.speed == Approx(std::sqrt(0.5 * 20000 * 30 * pitch)));
    CHECK(lineEnergy(out[18]) == Approx(1e-12 / pitch));  // the negligible dot, kept
}

// A laser with a minimum power (the galvo example's 1 mW): dots inside a row that need less than
// half of it were dropped, and each drop cut the row with a jump (its delays, 0.35 ms, are 0.1
// mm of marking at 300 mm/s). A short weak stretch is now marked at the minimum power, a long
// one still jumped over; weak dots do not cut the row into runs at other speeds either.
TEST_CASE("inside a row a weak stretch is marked at the minimum power when a jump costs more",
          "[plan]") {
    const double pitch = 0.02;
    LayerPlan layer;
    // 40 dots along x needing 3 mW at 300 mm/s; dots 10-12 (0.06 mm) and 25-34 (0.2 mm) 0.06 mW.
    for (int i = 0; i < 40; ++i) {
        const bool weak = (i >= 10 && i <= 12) || (i >= 25 && i <= 34);
        layer.points.push_back({i * pitch, 0, weak ? 4e-6 : 2e-4});
    }
    auto fitted = [&](double gapDelay, LimitFit& fit) {
        ScanPlan plan;
        plan.machine.laserPower = 10;
        plan.layers = {layer};
        LaserLimits l = limits(1.0);
        l.gapDelay = gapDelay;
        fit = fitPlanToLimits(plan, l, pitch);
        return plan.layers[0];
    };
    LimitFit fit;
    const LayerPlan out = fitted(350e-6, fit);
    CHECK(fit.raisedToMinPower == 3);
    CHECK(fit.droppedBelowMinPower == 10);
    REQUIRE(out.vectors.size() == 30);
    for (const LaserVector& v : out.vectors) {
        CHECK(v.speed == Approx(300));  // one run: the weak dots did not cut it
        CHECK(v.power >= 1.0 - 1e-12);
        CHECK(v.power <= 10 + 1e-12);
    }
    // The jumps of the fitted row: one, over the long stretch.
    CHECK(layerMoveTime(buildLayerTrajectory(out, 10, {}).moves, {}).jumps == 1);

    const LayerPlan dropped = fitted(0, fit);  // no delay to weigh: every weak stretch dropped
    CHECK(fit.droppedBelowMinPower == 13);
    CHECK(dropped.vectors.size() == 27);
    CHECK(layerMoveTime(buildLayerTrajectory(dropped, 10, {}).moves, {}).jumps == 2);
}
