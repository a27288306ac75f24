// The build-time model against a brute-force time integration of the same motion (issue 23):
// marks at constant speed, every change of speed in the jumps (skywriting), each axis with its
// own trapezoidal or triangular velocity profile under the machine limits, a jump as long as its
// slower axis. The integration drives each axis in small time steps with a bang-bang feedback
// law (accelerate or brake at the limit, hold at the speed limit, follow the final constant-
// acceleration arc into the target state), so it shares no closed form with scanner.cpp. Plans
// of hatching and of dot rows fitted to the limits (plan/machine/laser_limits.h).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "vpsim/plan/aces/aces.h"
#include "vpsim/plan/machine/build_time.h"
#include "vpsim/plan/machine/laser_limits.h"
#include "vpsim/plan/machine/trajectory.h"

using namespace vpsim;
using namespace vpsim::plan;
using geometry::PolygonSet;

namespace {

constexpr double DT = 2e-7;  // s: time step of the integration

double sign(double x) {
    return x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0;
}

/// Time for one axis to go from (0, v0) to (d, v1), integrated in steps of DT.
double integrateAxis(double d, double v0, double v1, const AxisLimits& limits) {
    const double a = limits.acceleration, vmax = limits.speed;
    double x = 0, v = v0, t = 0;
    // Distance the axis covers changing v to v1 at constant acceleration: the final arc.
    auto arc = [&](double u) {
        const double dv = v1 - u;
        return dv == 0 ? 0.0 : (v1 * v1 - u * u) / (2.0 * a * sign(dv));
    };
    const double side = sign((d - x) - arc(v));
    bool onArc = side == 0;
    for (long step = 0; step < 100000000L; ++step) {
        const double dv = v1 - v;
        if (!onArc && sign((d - x) - arc(v)) != side) onArc = true;
        double acc;
        if (onArc) {
            if (std::abs(dv) <= a * DT) return t + std::abs(dv) / a;  // arrives within a step
            acc = a * sign(dv);
        } else {
            acc = side * a;
            if (std::abs(v) >= vmax && sign(v) == side) acc = 0;  // cruise at the speed limit
        }
        const double next = std::clamp(v + acc * DT, -vmax, vmax);
        x += 0.5 * (v + next) * DT;
        v = next;
        t += DT;
    }
    FAIL("the integration did not converge");
    return t;
}

double integrateJump(const glm::dvec2& from, const glm::dvec2& to, const glm::dvec2& v0,
                     const glm::dvec2& v1, const AxisLimits& limits) {
    return std::max(integrateAxis(to.x - from.x, v0.x, v1.x, limits),
                    integrateAxis(to.y - from.y, v0.y, v1.y, limits));
}

/// The motion time (marks and jumps, without delays) of one layer's moves: the run-up from rest
/// into the first mark, each mark at its constant speed (or its dwell at rest), each gap between
/// marks crossed from the last mark's velocity to the next one's, and the run-out to rest.
double integrateLayer(const std::vector<ScanMove>& moves, const AxisLimits& machine) {
    std::vector<const ScanMove*> marks;
    for (const ScanMove& m : moves)
        if (m.laserOn) marks.push_back(&m);
    double t = 0;
    glm::dvec2 position{marks[0]->x0, marks[0]->y0}, velocity{0, 0};
    for (size_t k = 0; k < marks.size(); ++k) {
        const ScanMove& m = *marks[k];
        const glm::dvec2 start{m.x0, m.y0};
        const bool joined =
            std::abs(start.x - position.x) < 1e-9 && std::abs(start.y - position.y) < 1e-9;
        // A chained mark takes over at the corner (seed 002's polygon delay covers it); the
        // first mark is entered from rest.
        if (!joined || k == 0)
            t += integrateJump(position, start, velocity, startVelocity(m), machine);
        const double length = std::hypot(m.x1 - m.x0, m.y1 - m.y0);
        t += (length > 0 && m.speed > 0 ? length / m.speed : 0.0) + m.dwell;
        position = {m.x1, m.y1};
        velocity = endVelocity(m);
    }
    double runOut = 0;  // brake each axis to rest, wherever it stops
    for (double v : {velocity.x, velocity.y}) {
        double u = std::abs(v), s = 0;
        for (; u > machine.acceleration * DT; u -= machine.acceleration * DT) s += DT;
        runOut = std::max(runOut, s + u / machine.acceleration);
    }
    return t + runOut;
}

/// The model's mark and jump time of a layer's trajectory (10 mW dwells) against the integrated
/// motion, on a plan with more than 20 jumps and no mark above the process speed.
void checkAgainstIntegration(const LayerPlan& layer) {
    const BuildTimeOptions options;
    const LayerTrajectory trajectory = buildLayerTrajectory(layer, 10.0, {});
    const LayerTime model = layerMoveTime(trajectory.moves, options);
    const double integrated = integrateLayer(trajectory.moves, options.scanner.machine);
    INFO("model " << model.mark + model.jump << " s, integrated " << integrated << " s over "
                  << model.jumps << " jumps");
    REQUIRE(model.jumps > 20);
    CHECK(model.marksAboveProcessSpeed == 0);
    // Each jump's integration ends within a step of its target: at most a few DT per jump.
    CHECK(model.mark + model.jump == Approx(integrated).margin(4 * DT * double(model.jumps + 2)));
    CHECK(model.mark + model.jump == Approx(integrated).epsilon(1e-3));
}

}  // namespace

TEST_CASE("one axis: the closed form against the integrated motion", "[plan]") {
    const AxisLimits machine{2000.0, 20000.0};
    // Rest to rest, overshoot, reversal, cruise, keep-going, a change of speed and direction.
    const double cases[][3] = {{5, 0, 0},      {500, 0, 0},      {1, 300, 0},    {-10, 300, 0},
                               {0, 300, -300}, {0.02, 300, 300}, {3, -300, 300}, {40, 300, 100},
                               {0, 0, 300},    {-2, 1000, -1500}};
    for (const auto& c : cases) {
        INFO("d = " << c[0] << " mm, v0 = " << c[1] << " mm/s, v1 = " << c[2] << " mm/s");
        const double exact = axisMoveTime(c[0], c[1], c[2], machine);
        // The integration ends within one step of the target velocity: error O(DT) per phase.
        CHECK(integrateAxis(c[0], c[1], c[2], machine) == Approx(exact).margin(10 * DT));
    }
    // v1 = 0 is seed 002's jump (the original closed form).
    CHECK(axisMoveTime(1.0, 300, 0.0, machine) == Approx(axisMoveTime(1.0, 300, machine)));
}

TEST_CASE("build time of a small plan agrees with the integrated motion", "[plan]") {
    // An L-shaped layer hatched at the process speed, with its border loop, two separate parts
    // and a dwell point: jumps with every kind of entry and exit velocity.
    const PolygonSet region = PolygonSet::rectangle({0, 0}, {1, 0.4})
                                  .unite(PolygonSet::rectangle({0, 0}, {0.4, 1}))
                                  .unite(PolygonSet::rectangle({2, 2}, {2.5, 2.3}));
    LayerPlan layer;
    layer.vectors = contourLoops(region, 2.0, 300.0);
    const auto hatch = hatchRegion(region.offset(-0.05), 0.05, 0.3, 2.0, 250.0);
    layer.vectors.insert(layer.vectors.end(), hatch.begin(), hatch.end());
    layer.points.push_back({4, 0, 0.01});
    checkAgainstIntegration(layer);
}

TEST_CASE("build time of a fitted dot plan agrees with the integrated motion", "[plan]") {
    // Dot rows of an optimiser (a disc of dots 20 um apart with some dots missing and some
    // negligible), fitted to the limits: power-modulated scan lines at their paths' speeds, gaps
    // crossed at speed, reversals between lines, isolated dots as dwells.
    LayerPlan layer;
    const double pitch = 0.02;
    for (int j = -10; j <= 10; ++j)
        for (int i = -10; i <= 10; ++i) {
            if (i * i + j * j > 100 || (i == 3 && j % 3 == 0)) continue;
            const double energy = (i + j) % 7 == 0 ? 1e-12 : 1e-4 * (1 + 0.5 * std::sin(i + j));
            layer.points.push_back({i * pitch, j * pitch, energy});
        }
    layer.points.push_back({1, 1, 1e-4});  // isolated: a dwell
    ScanPlan plan;
    plan.machine.laserPower = 10;
    plan.layers = {layer};
    const BuildTimeOptions options;
    LaserLimits limits;
    limits.powerMax = 10, limits.processSpeed = options.scanner.process.speed;
    limits.beamRadius = 0.05, limits.negligibleDose = 0.001;
    limits.jumpAcceleration = options.scanner.machine.acceleration;
    fitPlanToLimits(plan, limits, pitch);
    REQUIRE(!plan.layers[0].points.empty());  // the isolated dot at least
    checkAgainstIntegration(plan.layers[0]);
}
