// The laser exposure-error metric taken from the streamed slices (ExposureErrorSink) against the
// standalone one (planExposureError, each layer exposed again), tiled against untiled, and its
// state through a save / restore and the ranks' merge.
#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/exposure/tiles.h"
#include "vpsim/optimise/laser/dfbtp.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/optimise/laser/exposure_error_sink.h"
#include "vpsim/plan/feature_blocks.h"

using namespace vpsim;

namespace {

/// Three layers of a DFBTP plan: an L, the same L, and a square on top, so that the lower
/// layers' error includes the upper layers' print-through (De3D 36.7 um, 50 um layers:
/// exp(-lt/De) = 0.26), with the default job's fitted kernel and five slices per layer.
struct Case {
    kernel::FittedBeam beam{0.0632, 0.0367, 0.0022, 2.37};
    static constexpr double LT = 0.05;
    static constexpr int SLICES = 5;
    std::vector<geometry::PolygonSet> regions;
    plan::ScanPlan plan;
    double etar = 0, band = 0;
    exposure::ExposureGrid grid;  ///< planningGrid with SLICES slices per layer

    Case() {
        auto a = geometry::PolygonSet::rectangle({0, 0}, {1.0, 0.5});
        auto b = geometry::PolygonSet::rectangle({0, 0.5}, {0.5, 1.0});
        const auto l = a.unite(b).translated({-0.5, -0.5});
        regions = {l, l, geometry::PolygonSet::rectangle({-0.3, -0.3}, {0.2, 0.2})};
        optimise::DfbtpParameters p;
        p.aces.beamRadius = beam.radius;
        p.aces.attenuationLength = beam.attenuationLength;
        p.aces.depthOfMaximum = beam.depthOfMaximum;
        p.aces.criticalDose = 0.1 / beam.efficiency;
        p.aces.layerThickness = LT;
        p.aces.laserPower = 10.0;
        const optimise::DfbtpResult r = optimise::planDfbtp(regions, {LT, 2 * LT, 3 * LT}, p, beam);
        plan = r.plan;
        etar = r.targetDose;
        band = plan::effectiveRadius(beam.radius);
        grid = optimise::planningGrid(regions, beam.radius, 0.01);
        grid.slicesPerLayer = SLICES;
    }
    /// Slice 0 is dz/2 below the layer's top: exp(dz/(2 De)) gives the surface (exact for the
    /// fitted kernel).
    double surfaceScale() const { return std::exp(0.5 * LT / SLICES / beam.attenuationLength); }
    optimise::ExposureErrorSink sink(bool topMap = false) const {
        return optimise::ExposureErrorSink(grid, regions, etar, band, surfaceScale(), topMap);
    }
    /// Every slice of the run, whole grid, into `sink`.
    void runWhole(optimise::ExposureErrorSink& sink) const {
        exposure::ExposureEngine engine(grid, beam, LT);
        engine.run(plan, [&](const exposure::ExposureSlice& s) { sink.add(s); });
    }
    std::vector<exposure::Tile> tiles() const {
        exposure::ExposureEngine engine(grid, beam, LT);
        return exposure::tileLayout(grid, 40, engine.reachCells() + 1);
    }
    /// One tile's slices into `sink`.
    void runTile(const exposure::Tile& tile, optimise::ExposureErrorSink& sink) const {
        exposure::ExposureEngine engine(grid.window(tile.window), beam, LT);
        engine.run(plan, tile.core, [&](const exposure::ExposureSlice& s) { sink.add(s); });
    }
};

/// Every figure of two results, the sums to `relative`, counts and maxima as given.
void compareResults(const nlohmann::json& a, const nlohmann::json& b, double relative) {
    REQUIRE(a["layers"].size() == b["layers"].size());
    for (size_t k = 0; k < a["layers"].size(); ++k) {
        INFO("layer row " << k);
        const auto &x = a["layers"][k], &y = b["layers"][k];
        CHECK(x["layer"] == y["layer"]);
        for (const char* key : {"sse_mJ2_per_mm4", "rms_over_Etar", "max_over_Etar"})
            CHECK(x[key].get<double>() == Approx(y[key].get<double>()).epsilon(relative));
    }
    for (const char* key : {"sse_mJ2_per_mm4", "rms_over_Etar", "max_over_Etar"})
        CHECK(a[key].get<double>() == Approx(b[key].get<double>()).epsilon(relative));
}

}  // namespace

// The streamed slice 0 is the engine's exp(-dz/(2 De)) R_k, the standalone review's R_k its own
// recursion over per-layer blurs: the same quantity by two computations on the same cells, so
// the cells counted agree exactly and the figures to float rounding (a float per cell, summed
// in double: 1e-5 relative covers the few ulps of the blur and recursion in float).
TEST_CASE("the streamed exposure error equals the standalone one", "[optimise][exposure_error]") {
    const Case c;
    exposure::ExposureEngine standaloneEngine(c.grid, c.beam, Case::LT);
    optimise::ExposureError standaloneAll, streamedAll;
    exposure::SurfaceGrid standaloneTop;
    const nlohmann::json standalone = optimise::planExposureError(
        standaloneEngine, c.plan, c.regions, c.etar, c.band, &standaloneAll, &standaloneTop);
    auto sink = c.sink(true);
    c.runWhole(sink);
    const nlohmann::json streamed = sink.result(&streamedAll);
    REQUIRE(standalone["layers"].size() == 3);
    compareResults(streamed, standalone, 1e-5);
    CHECK(streamedAll.cells == standaloneAll.cells);
    CHECK(streamed["top_layer"]["sse_mJ2_per_mm4"].get<double>() ==
          Approx(standalone["top_layer"]["sse_mJ2_per_mm4"].get<double>()).epsilon(1e-5));
    // The print-through matters here: the lowest layer's error differs from the middle one's.
    CHECK(std::abs(streamed["layers"][0]["sse_mJ2_per_mm4"].get<double>() -
                   streamed["layers"][1]["sse_mJ2_per_mm4"].get<double>()) >
          1e-3 * streamed["layers"][1]["sse_mJ2_per_mm4"].get<double>());
    // The sorted curve from the histogram: a value within float rounding of a bin edge may
    // move one bin (1/16384 Etar).
    REQUIRE(streamedAll.sortedRelative.size() == standaloneAll.sortedRelative.size());
    for (size_t q = 0; q < streamedAll.sortedRelative.size(); ++q)
        CHECK(streamedAll.sortedRelative[q] ==
              Approx(standaloneAll.sortedRelative[q]).margin(1.01 / 16384));
    // The top layer's surface exposure, cell by cell.
    const exposure::SurfaceGrid& top = sink.topMap();
    REQUIRE(top.values.size() == standaloneTop.values.size());
    double peak = 0, worst = 0;
    for (size_t i = 0; i < top.values.size(); ++i) {
        peak = std::max(peak, double(standaloneTop.values[i]));
        worst = std::max(worst, std::abs(double(top.values[i]) - standaloneTop.values[i]));
    }
    CHECK(peak > c.etar / 2);
    CHECK(worst < 1e-5 * peak);
    // Without the depth correction the slice is exp(-dz/(2 De)) = 0.87 of the surface: the
    // figures differ, so the comparison above can fail.
    optimise::ExposureErrorSink uncorrected(c.grid, c.regions, c.etar, c.band, 1.0, false);
    c.runWhole(uncorrected);
    CHECK(uncorrected.result()["sse_mJ2_per_mm4"].get<double>() !=
          Approx(standalone["sse_mJ2_per_mm4"].get<double>()).epsilon(0.01));
}

// A tile's core cells get the untiled dose bit for bit (exposure/tiles.h): the counts, maxima
// and histogram agree exactly, the sums to double rounding (per tile, added in the tiles' order,
// instead of per row of the whole grid).
TEST_CASE("the streamed exposure error is the same tiled and untiled",
          "[optimise][exposure_error]") {
    const Case c;
    const std::vector<exposure::Tile> tiles = c.tiles();
    REQUIRE(tiles.size() >= 4);
    auto whole = c.sink(true), tiled = c.sink(true);
    c.runWhole(whole);
    for (const exposure::Tile& tile : tiles) c.runTile(tile, tiled);
    optimise::ExposureError wholeAll, tiledAll;
    const nlohmann::json a = whole.result(&wholeAll), b = tiled.result(&tiledAll);
    compareResults(a, b, 1e-12);
    for (size_t k = 0; k < a["layers"].size(); ++k)
        CHECK(a["layers"][k]["max_over_Etar"] == b["layers"][k]["max_over_Etar"]);
    CHECK(wholeAll.cells == tiledAll.cells);
    CHECK(wholeAll.sortedRelative == tiledAll.sortedRelative);
    CHECK(whole.topMap().values == tiled.topMap().values);
}

// A checkpoint (save after some tiles, restore into a new sink, go on) and the ranks' merge
// (each tile into a fresh sink, states merged in the tiles' order) give the one-process tiled
// figures bit for bit; a malformed state is refused.
TEST_CASE("the exposure-error state survives a checkpoint and the ranks' merge",
          "[optimise][exposure_error]") {
    const Case c;
    const std::vector<exposure::Tile> tiles = c.tiles();
    auto single = c.sink();
    for (const exposure::Tile& tile : tiles) c.runTile(tile, single);
    const nlohmann::json expected = single.result();

    auto before = c.sink();
    const size_t half = tiles.size() / 2;
    for (size_t i = 0; i < half; ++i) c.runTile(tiles[i], before);
    const nlohmann::json saved = nlohmann::json::parse(before.saveState().dump());
    auto resumed = c.sink();
    resumed.restoreState(saved);
    for (size_t i = half; i < tiles.size(); ++i) c.runTile(tiles[i], resumed);
    CHECK(resumed.result() == expected);

    auto merged = c.sink();
    for (const exposure::Tile& tile : tiles) {
        auto rank = c.sink();
        c.runTile(tile, rank);
        merged.mergeState(nlohmann::json::parse(rank.saveState().dump()));
    }
    CHECK(merged.result() == expected);

    nlohmann::json broken = saved;
    broken["layers"][0][0] = 7;
    CHECK_THROWS_AS(c.sink().restoreState(broken), InputError);
    CHECK_THROWS_AS(c.sink().restoreState(nlohmann::json::object()), InputError);
}
