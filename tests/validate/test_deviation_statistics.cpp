// The cured surface's deviation statistics (issue 22: statistics that do not grow with the
// surface): without kept triangles the mesher holds a layer of vertices, not the surface, and
// its running statistics match brute force over every vertex's deviation (kept with the
// triangles), untiled and in x-y tiles.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "vpsim/core/io.h"
#include "vpsim/exposure/tiles.h"
#include "vpsim/geometry/test_parts.h"
#include "vpsim/validate/streaming_surface.h"

using namespace vpsim;

namespace {

constexpr double BAND = 0.5, DZ = 0.02;  // a band that clamps none
constexpr int SLICES = 40;

/// Feeds slices of 2 exp(-(r/R)^2) about (0, 0, 0.4) (cured inside r = 0.3 mm), top down,
/// tile after tile; returns the most vertices the surface held after a slice.
size_t feed(validate::StreamingCuredSurface& surface, const exposure::ExposureGrid& grid,
            const std::vector<exposure::Tile>& tiles, bool finish = true) {
    const double R = 0.3 / std::sqrt(std::log(2.0));
    exposure::SurfaceGrid values = grid.surface();
    size_t held = 0;
    for (const exposure::Tile& tile : tiles)
        for (int k = SLICES - 1; k >= 0; --k) {
            const double z = (k + 0.5) * DZ;
            for (int j = 0; j < grid.ny; ++j)
                for (int i = 0; i < grid.nx; ++i) {
                    const glm::dvec3 d =
                        glm::dvec3(values.centreX(i), values.centreY(j), z) - glm::dvec3(0, 0, 0.4);
                    values.at(i, j) = float(2.0 * std::exp(-glm::dot(d, d) / (R * R)));
                }
            surface.add({0, SLICES - 1 - k, z, &values, tile.core});
            held = std::max(held, surface.vertices().size());
        }
    if (finish) surface.finish();
    return held;
}

}  // namespace

TEST_CASE("deviation statistics without the vertices match brute force, tiled or not",
          "[validate]") {
    geometry::TestPartOptions options;
    options.size = 0.5;
    options.height = 0.7;
    const geometry::Mesh part =
        geometry::makeTestPart("box", options);  // [-0.25, 0.25]^2 x [0, 0.7]
    const auto grid = exposure::ExposureGrid::covering(-0.4, -0.4, 0.4, 0.4, 0.0, 0.02, 1);
    const auto whole = exposure::tileLayout(grid, 0, 2);
    const auto tiled = exposure::tileLayout(grid, 13, 2);
    REQUIRE(tiled.size() > 4);

    validate::StreamingCuredSurface kept(grid, DZ, 1.0, &part, BAND, "");
    kept.keepTriangles(true);
    feed(kept, grid, whole);
    const std::vector<float>& all = kept.deviations();
    REQUIRE(all.size() == kept.statistics().count());
    REQUIRE(all.size() > 2000);
    // Brute force over every vertex.
    double sum = 0, sumSq = 0;
    std::vector<float> magnitude;
    for (float d : all) {
        sum += d;
        sumSq += double(d) * d;
        magnitude.push_back(std::abs(d));
    }
    std::sort(magnitude.begin(), magnitude.end());
    const size_t rank = size_t(std::ceil(0.95 * double(all.size()))) - 1;
    const double bin = BAND / validate::DeviationStatistics::BINS;

    for (const auto* layout : {&whole, &tiled}) {
        validate::StreamingCuredSurface streamed(grid, DZ, 1.0, &part, BAND, "");
        const size_t held = feed(streamed, grid, *layout);
        INFO("tiles " << layout->size());
        CHECK(held < all.size() / 10);  // a layer or two, not the surface
        CHECK(streamed.triangles() == kept.triangles());
        CHECK(streamed.volume() == Approx(kept.volume()).epsilon(1e-9));
        const validate::DeviationStatistics& s = streamed.statistics();
        REQUIRE(s.count() == all.size());
        const validate::SurfaceDeviation d = s.summary();
        CHECK(d.mean == Approx(sum / double(all.size())).epsilon(1e-9));
        CHECK(d.rms == Approx(std::sqrt(sumSq / double(all.size()))).epsilon(1e-9));
        CHECK(d.max == magnitude.back());
        CHECK(std::abs(d.p95 - magnitude[rank]) <= bin);
        CHECK(d.p95 >= magnitude[rank] - 1e-9);
        CHECK(d.beyondBand == 0);
        for (double limit : {0.01, 0.03, 0.05}) {  // exact but for samples within a bin
            const auto count = [&](auto predicate) {
                return double(std::count_if(magnitude.begin(), magnitude.end(), predicate));
            };
            const double exact = count([&](float m) { return m > limit; });
            const double near = count([&](float m) { return std::abs(m - limit) <= bin; });
            CHECK(std::abs(double(s.countAbove(limit)) - exact) <= near);
        }
    }
}

TEST_CASE("deviation statistics merge in order and survive their JSON state", "[validate]") {
    validate::DeviationStatistics a(0.25), b(0.25), both(0.25);
    for (int i = 0; i < 1000; ++i) {
        const float d = float(0.3 * std::sin(0.37 * i));  // some beyond the band
        (i < 400 ? a : b).add(d);
    }
    both = a;
    both.merge(b);
    CHECK(both.count() == 1000);
    const validate::DeviationStatistics back =
        validate::DeviationStatistics::fromJson(nlohmann::json::parse(both.toJson().dump()));
    CHECK(back.toJson() == both.toJson());
    const validate::SurfaceDeviation x = back.summary(), y = both.summary();
    CHECK(x.mean == y.mean);
    CHECK(x.rms == y.rms);
    CHECK(x.p95 == y.p95);
    CHECK(x.beyondBand == y.beyondBand);
    CHECK(x.beyondBand > 0);
    CHECK_THROWS(validate::DeviationStatistics::fromJson(nlohmann::json{{"band", 0.25}}));
    CHECK_THROWS(validate::DeviationStatistics(0.25).summary());
}

// What MPI ranks do with a job's tiles (pipeline/cluster_run.h): each tile into a fresh surface
// with an in-place STL, its saved state and STL triangles merged in the tiles' order into
// another surface, gives one surface fed every tile: the same counts, volume and statistics to
// the bit, and the same STL bytes.
TEST_CASE("cured surfaces of single tiles merged in order are the surface of all tiles",
          "[validate]") {
    geometry::TestPartOptions options;
    options.size = 0.5;
    options.height = 0.7;
    const geometry::Mesh part = geometry::makeTestPart("box", options);
    const auto grid = exposure::ExposureGrid::covering(-0.4, -0.4, 0.4, 0.4, 0.0, 0.02, 1);
    const auto tiles = exposure::tileLayout(grid, 13, 2);
    const auto dir = std::filesystem::temp_directory_path();
    const std::string oneStl = (dir / "vpsim_merge_one.stl").string(),
                      mergedStl = (dir / "vpsim_merge_merged.stl").string();

    validate::StreamingCuredSurface one(grid, DZ, 1.0, &part, BAND, oneStl);
    feed(one, grid, tiles);
    validate::StreamingCuredSurface merged(grid, DZ, 1.0, &part, BAND, mergedStl);
    for (const exposure::Tile& tile : tiles) {
        const std::string tileStl = (dir / "vpsim_merge_tile.stl").string();
        nlohmann::json state;
        {
            validate::StreamingCuredSurface alone(
                grid, DZ, 1.0, &part, BAND, validate::StreamingCuredSurface::InPlaceStl{tileStl});
            feed(alone, grid, {tile}, false);
            state = alone.saveState();
        }
        merged.mergeState(nlohmann::json::parse(state.dump()), readFile(tileStl).substr(84));
    }
    merged.finish();
    CHECK(merged.triangles() == one.triangles());
    CHECK(merged.volume() == one.volume());
    CHECK(merged.statistics().toJson() == one.statistics().toJson());
    CHECK(readFile(mergedStl) == readFile(oneStl));
}
