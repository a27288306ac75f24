// Trajectories (parts, borders, jumps, point rows) and the seed-002 build-time model (Eq. 1-4).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "support/svg_text.h"
#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/plan/aces/aces.h"
#include "vpsim/plan/machine/build_time.h"
#include "vpsim/plan/machine/part_grouping.h"
#include "vpsim/plan/machine/scan_report.h"
#include "vpsim/plan/machine/trajectory.h"
#include "vpsim/plan/machine/transition_arc.h"

using namespace vpsim;
using namespace vpsim::plan;
using geometry::PolygonSet;

TEST_CASE("delays and times of a hand-counted layer (seed 002 Eq. 1-4)", "[plan]") {
    // A 2-vector polyline, then a separate vector: 3 marks, 1 polygon delay, 1 jump (jump
    // delay), 2 mark delays (before the jump and at the end of the layer).
    LayerPlan layer;
    layer.vectors = {{0, 0, 3, 0, 10, 300}, {3, 0, 3, 3, 10, 300}, {10, 3, 10, 0, 10, 150}};
    BuildTimeOptions options;
    LayerTime t = layerMoveTime(buildLayerTrajectory(layer, 10, {}).moves, options);
    CHECK(t.marks == 3);
    CHECK(t.polygonDelays == 1);
    CHECK(t.jumps == 1);
    CHECK(t.jumpDelays == 1);
    CHECK(t.markDelays == 2);
    CHECK(t.marksAboveProcessSpeed == 0);
    CHECK(t.mark == Approx(3.0 / 300 + 3.0 / 300 + 3.0 / 150));
    CHECK(t.delays == Approx(250e-6 + 2 * 100e-6 + 50e-6));
    // The jump (3,3) -> (10,3) leaves with +y 300 mm/s and enters the last mark at -y 150 mm/s
    // (skywriting): x needs 7 mm from rest to rest, y reverses. Before it the run-up into the
    // first mark (+x 300 mm/s from rest at (0,0)), after it the run-out from -y 150 mm/s.
    const AxisLimits& machine = options.scanner.machine;
    const double runUp = jumpTime({0, 0}, {0, 0}, {0, 0}, {300, 0}, machine);
    CHECK(runUp == Approx(300 * (1 + std::sqrt(2.0)) / 20000));  // back up, then accelerate
    CHECK(t.jump ==
          Approx(runUp + jumpTime({3, 3}, {10, 3}, {0, 300}, {0, -150}, machine) + 150.0 / 20000));
    // Independently of jumpTime: x alone needs 7 mm from rest to rest, triangular under 20 m/s^2
    // (7 mm < v^2/a = 200 mm): 2 sqrt(7 / 20000) s; the jump cannot be shorter.
    CHECK(jumpTime({3, 3}, {10, 3}, {0, 300}, {0, -150}, machine) >=
          2 * std::sqrt(7.0 / 20000.0) * (1 - 1e-12));
    CHECK(t.total() == Approx(t.mark + t.jump + t.delays));

    ScanPlan plan;
    plan.layers = {layer, layer};
    options.recoatTime = 5.0;
    BuildTime whole = estimateBuildTime(plan, options);
    CHECK(whole.sum.recoat == Approx(10.0));
    CHECK(whole.total() == Approx(2 * t.total() + 10.0));
    nlohmann::json json = whole.toJson();
    for (const char* key : {"total", "mark", "jump", "delays", "recoat"}) CHECK(json.contains(key));
    CHECK(json["total"].get<double>() == Approx(whole.total()));
}

TEST_CASE("parts are grouped by proximity or by region, borders first", "[plan]") {
    PolygonSet region = PolygonSet::rectangle({0, 0}, {1, 1})
                            .unite(PolygonSet::rectangle({3, 0}, {4, 1}))
                            .unite(PolygonSet::rectangle({0, 3}, {1, 4}));
    LayerPlan layer;
    layer.vectors = hatchRegion(region, 0.05, 0.0, 10, 300);  // rows cross all parts
    // A closed border around the first square, listed after the hatches.
    const double b[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
    for (int k = 0; k < 4; ++k)
        layer.vectors.push_back({b[k][0], b[k][1], b[k + 1][0], b[k + 1][1], 10, 300});
    PartGroups byGap = groupLayerParts(layer, 0.2), byRegion = groupLayerParts(layer, 0.2, &region);
    CHECK(byGap.vectors.size() == 3);
    CHECK(byRegion.vectors.size() == 3);
    LayerTrajectory t = buildLayerTrajectory(layer, 10, {}, &region);
    CHECK(t.parts == 3);
    CHECK(t.order.provenOptimal);
    CHECK(t.order.cost <= t.order.nearestNeighbourCost + 1e-12);
    size_t marks = 0;
    for (const ScanMove& m : t.moves) marks += m.laserOn;
    // The border is split once at the point closest to its part's first hatch start (a dummy
    // vertex, seed 002 Fig. 7) unless that point is a vertex.
    CHECK((marks == layer.vectors.size() || marks == layer.vectors.size() + 1));
    // Each part is scanned in one go, and moves join end to start.
    int switches = 0;
    for (size_t i = 1; i < t.moves.size(); ++i) {
        switches += t.moves[i].part != t.moves[i - 1].part;
        CHECK(t.moves[i].x0 == Approx(t.moves[i - 1].x1).margin(1e-9));
        CHECK(t.moves[i].y0 == Approx(t.moves[i - 1].y1).margin(1e-9));
    }
    CHECK(switches == 2);
}

TEST_CASE("points: modulated rows give each point its energy by power; dwell is the alternative",
          "[plan]") {
    LayerPlan layer;
    const double power = 10, energy = 0.004;  // 0.4 ms per point: 250 mm/s over 0.1 mm
    for (int i = 0; i < 5; ++i) layer.points.push_back({0.1 * i, 0.0, energy});
    for (int i = 0; i < 5; ++i) layer.points.push_back({0.1 * i, 0.1, 2 * energy});
    TrajectoryOptions modulated;
    LayerTrajectory m = buildLayerTrajectory(layer, power, modulated);
    double delivered = 0;
    for (const ScanMove& move : m.moves)
        if (move.laserOn)
            delivered +=
                move.power *
                (std::hypot(move.x1 - move.x0, move.y1 - move.y0) / move.speed + move.dwell);
    CHECK(delivered == Approx(15 * energy));
    TrajectoryOptions dwell;
    dwell.points = PointStrategy::Dwell;
    LayerTrajectory d = buildLayerTrajectory(layer, power, dwell);
    BuildTimeOptions options;
    LayerTime tm = layerMoveTime(m.moves, options), td = layerMoveTime(d.moves, options);
    CHECK(tm.mark == Approx(15 * energy / power));
    CHECK(td.mark == Approx(15 * energy / power));
    CHECK(td.jumps == 9);
    CHECK(tm.jumps == 1);  // one row change
    // Each modulated row is entered and left at speed (a reversal costs 2 v / a in the jump), so
    // on these short, sparse rows the dwells are faster; point_build_time_s reports both.
    CHECK(tm.jump > 2 * 125.0 / 20000);
    // Little energy: the row runs at the process speed and the power drops, so every point
    // still gets exactly its energy.
    LayerPlan fast;
    for (int i = 0; i < 3; ++i) fast.points.push_back({0.1 * i, 0, 1e-7});
    for (const ScanMove& move : buildLayerTrajectory(fast, power, modulated).moves) {
        if (!move.laserOn) continue;
        CHECK(move.speed == Approx(modulated.scanner.process.speed));
        CHECK(move.power * std::hypot(move.x1 - move.x0, move.y1 - move.y0) / move.speed ==
              Approx(1e-7));
    }
}

TEST_CASE("trajectories are saved with the plan", "[plan]") {
    ScanPlan plan;
    LayerPlan layer;
    layer.z = 0.05;
    layer.vectors = hatchRegion(PolygonSet::rectangle({0, 0}, {1, 1}), 0.1, 0.0, 10, 300);
    plan.layers.push_back(layer);
    attachTrajectories(plan, buildTrajectories(plan, {}));
    const size_t moves = plan.layers[0].trajectory.size();
    REQUIRE(moves > layer.vectors.size());
    auto path = (std::filesystem::temp_directory_path() / "vpsim_traj_plan.json").string();
    saveScanPlan(plan, path);
    ScanPlan loaded = loadScanPlan(path);
    REQUIRE(loaded.layers[0].trajectory.size() == moves);
    CHECK(loaded.layers[0].trajectory[1].laserOn == plan.layers[0].trajectory[1].laserOn);
    CHECK(loaded.layers[0].trajectory[2].x1 == plan.layers[0].trajectory[2].x1);
    BuildTimeOptions options;
    CHECK(estimateBuildTime(loaded, options).total() ==
          Approx(estimateBuildTime(plan, options).total()));
    std::filesystem::remove(path);
}

TEST_CASE("DLP build time from mask exposure and recoat", "[plan]") {
    ScanPlan plan;
    LayerPlan layer;
    MaskImage mask;
    mask.width = 2, mask.height = 1, mask.pixelPitch = 0.05, mask.dose = {0.5f, 1.0f};
    layer.masks.push_back(mask);
    plan.layers = {layer, layer, layer};
    ConfigNode machine(
        nlohmann::json{{"recoat_time", "4 s"}, {"projector_irradiance", "0.2 mW/mm^2"}},
        "machine.json");
    BuildTimeOptions options = buildTimeOptionsFromConfig(machine);
    BuildTime t = estimateBuildTime(plan, options);
    CHECK(t.sum.exposure == Approx(3 * 1.0 / 0.2));
    CHECK(t.total() == Approx(15.0 + 12.0));
    options.projectorIrradiance = 0;
    CHECK_THROWS_WITH(estimateBuildTime(plan, options), Catch::Contains("projector_irradiance"));
}

TEST_CASE("report pieces: scan_order, point strategies, plan keys, scan-path SVG", "[plan]") {
    ScanPlan plan;
    plan.machine.laserPower = 10;
    LayerPlan layer;
    for (int i = 0; i < 4; ++i) layer.points.push_back({0.1 * i, 0, 0.004});
    for (int i = 0; i < 4; ++i) layer.points.push_back({5 + 0.1 * i, 0, 0.004});
    plan.layers = {layer, LayerPlan{}};
    TrajectoryOptions options;
    auto layers = buildTrajectories(plan, options);
    nlohmann::json order = scanOrderJson(layers);
    REQUIRE(order["layers"].size() == 1);  // the empty layer is left out
    CHECK(order["layers"][0]["parts"] == 2);
    CHECK(order["layers"][0]["method"] == "exact");
    CHECK(order["layers"][0]["proven_optimal"] == true);
    CHECK(order.contains("nearest_neighbour_jump_time_s"));
    nlohmann::json points = pointStrategyJson(plan, options, BuildTimeOptions{});
    CHECK(points["modulated_s"].get<double>() < points["dwell_s"].get<double>());
    CHECK(pointStrategyJson(ScanPlan{}, options, BuildTimeOptions{}).is_null());

    const auto stem = (std::filesystem::temp_directory_path() / "vpsim_scan_path").string();
    const std::string svg = stem + ".svg";
    writeScanPathFigure(stem, layers[busiestLayer(layers)].moves, "scan path");
    const std::string text = readFile(svg);
    CHECK(test::hasText(text, "jumps between parts"));
    CHECK(test::hasText(text, "x (mm)"));
    CHECK(std::filesystem::exists(stem + ".png"));
    std::filesystem::remove(svg);
    std::filesystem::remove(stem + ".png");
}

TEST_CASE("transition arcs replace stop-and-go jumps when faster", "[plan]") {
    // Two collinear marks in the same direction with a 0.5 mm gap: the arcs have no sweep and the
    // straight segment keeps the beam moving (0.0016 s) where stop-and-go overshoots (0.036 s).
    std::vector<ScanMove> moves(2);
    moves[0].laserOn = moves[1].laserOn = true;
    moves[0].speed = moves[1].speed = 300;
    moves[0].x1 = 1, moves[1].x0 = 1.5, moves[1].x1 = 2.5;
    BuildTimeOptions options;
    LayerTime stop = layerMoveTime(moves, options);
    options.transitionArcs = true;
    LayerTime arcs = layerMoveTime(moves, options);
    CHECK(stop.jumps == 1);
    CHECK(arcs.arcs == 1);
    CHECK(arcs.jumps == 0);
    CHECK(arcs.jumpDelays == 0);
    CHECK(arcs.markDelays == 1);  // only the laser-off at the end of the layer
    // Plus the run-up into the first mark (from rest) and the run-out after the last.
    const double runUp = jumpTime({0, 0}, {0, 0}, {0, 0}, {300, 0}, options.scanner.machine);
    CHECK(arcs.jump ==
          Approx(runUp + segmentTime(0.5, 300, 300, options.scanner.machine) + 300.0 / 20000));
    CHECK(arcs.total() < stop.total());
    // A reversal (zig-zag) keeps stop-and-go: a U-turn of radius 3 v^2/a = 600 mm is far slower.
    moves[1].x0 = 1, moves[1].y0 = 0.05, moves[1].x1 = 0, moves[1].y1 = 0.05;
    CHECK(layerMoveTime(moves, options).arcs == 0);
}

TEST_CASE("scheduleScans: laser plans get trajectories, DLP plans a mask time", "[plan]") {
    ScanPlan laser;
    LayerPlan layer;
    layer.vectors = hatchRegion(
        PolygonSet::rectangle({0, 0}, {1, 1}).unite(PolygonSet::rectangle({2, 0}, {3, 1})), 0.1,
        0.0, 10, 300);
    laser.layers = {layer};
    ScanSchedule s = scheduleScans(laser, {}, {});
    CHECK_FALSE(laser.layers[0].trajectory.empty());
    CHECK(s.scanOrder["layers"][0]["parts"] == 2);
    CHECK(s.buildTime["total"].get<double>() > 0);
    CHECK(s.pointStrategies.is_null());

    ScanPlan dlp;
    LayerPlan maskLayer;
    MaskImage mask;
    mask.width = 1, mask.height = 1, mask.pixelPitch = 0.05, mask.dose = {1.0f};
    maskLayer.masks = {mask};
    dlp.layers = {maskLayer};
    BuildTimeOptions timing;
    timing.recoatTime = 3;
    ScanSchedule d = scheduleScans(dlp, {}, timing);
    CHECK(d.buildTime["total"].is_null());
    CHECK(d.buildTime["recoat"].get<double>() == Approx(3));
    timing.projectorIrradiance = 0.5;
    CHECK(scheduleScans(dlp, {}, timing).buildTime["total"].get<double>() == Approx(5));
}

TEST_CASE("choosing entry points never lengthens the jumps (between and inside parts)", "[plan]") {
    PolygonSet region;
    for (int i = 0; i < 6; ++i)
        region = region.unite(
            PolygonSet::rectangle({1.7 * i, 0.9 * (i % 3)}, {1.7 * i + 0.5, 0.9 * (i % 3) + 0.5}));
    LayerPlan layer;
    layer.vectors = hatchRegion(region, 0.05, M_PI / 2, 10, 300);
    TrajectoryOptions fixed, free;
    free.chooseEntry = true;
    LayerTrajectory a = buildLayerTrajectory(layer, 10, fixed, &region);
    LayerTrajectory b = buildLayerTrajectory(layer, 10, free, &region);
    size_t marksA = 0, marksB = 0;
    for (const auto& m : a.moves) marksA += m.laserOn;
    for (const auto& m : b.moves) marksB += m.laserOn;
    CHECK(marksA == marksB);
    BuildTimeOptions timing;
    CHECK(layerMoveTime(b.moves, timing).jump <= layerMoveTime(a.moves, timing).jump + 1e-9);
    if (b.reversedParts == 0) CHECK(b.order.cost == a.order.cost);
}
