// The cured surface's deviation statistics (issue 22: statistics that do not grow with the
// surface): without kept triangles the mesher holds a layer of vertices, not the surface, and
// its running statistics match brute force over every vertex's deviation (kept with the
// triangles), untiled and in x-y tiles; so does the clustered picture kept for the report.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "vpsim/core/binary_state.h"
#include "vpsim/core/io.h"
#include "vpsim/exposure/tiles.h"
#include "vpsim/geometry/test_parts.h"
#include "vpsim/validate/streaming_surface.h"
#include "vpsim/validate/surface_clusters.h"

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

/// The box [-0.25, 0.25]^2 x [0, 0.7] (the part) and a 20 um grid around it.
geometry::Mesh boxPart() {
    geometry::TestPartOptions options;
    options.size = 0.5;
    options.height = 0.7;
    return geometry::makeTestPart("box", options);
}
exposure::ExposureGrid boxGrid() {
    return exposure::ExposureGrid::covering(-0.4, -0.4, 0.4, 0.4, 0.0, 0.02, 1);
}

}  // namespace

TEST_CASE("deviation statistics without the vertices match brute force, tiled or not",
          "[validate]") {
    const geometry::Mesh part = boxPart();
    const auto grid = boxGrid();
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

// The report's histogram of the signed deviation comes from the statistics, not from a value per
// vertex: the same counts as binning the samples (but for samples within a fine bin of a coarse
// bin's edge), the extremes exact, and the end bins taking what lies outside.
TEST_CASE("deviation statistics give the signed histogram and the extremes", "[validate]") {
    validate::DeviationStatistics s(0.25);
    std::vector<float> samples;
    for (int i = 0; i < 5000; ++i) samples.push_back(float(0.2 * std::sin(0.61 * i) - 0.03));
    for (float d : samples) s.add(d);
    CHECK(s.minimum() == double(*std::min_element(samples.begin(), samples.end())));
    CHECK(s.maximum() == double(*std::max_element(samples.begin(), samples.end())));
    const double lo = -0.15, hi = 0.15, fine = 0.25 / validate::DeviationStatistics::BINS;
    const int bins = 12;
    const std::vector<uint64_t> counts = s.histogram(lo, hi, bins);
    REQUIRE(counts.size() == size_t(bins));
    std::vector<double> exact(bins, 0.0), nearEdge(bins, 0.0);
    for (float d : samples) {
        const double x = (d - lo) / (hi - lo) * bins;
        exact[std::clamp(int(std::floor(x)), 0, bins - 1)] += 1;
        const double edge = std::round(x);
        if (std::abs(x - edge) * (hi - lo) / bins <= fine && edge > 0 && edge < bins) {
            nearEdge[int(edge) - 1] += 1;  // may fall on either side
            nearEdge[int(edge)] += 1;
        }
    }
    double total = 0;
    for (int b = 0; b < bins; ++b) {
        CHECK(std::abs(double(counts[b]) - exact[b]) <= nearEdge[b]);
        total += double(counts[b]);
    }
    CHECK(total == double(samples.size()));
    CHECK(exact.front() > 0);  // the end bins hold what lies beyond [lo, hi]
    CHECK(exact.back() > 0);
    CHECK_THROWS(s.histogram(0.1, 0.1, 4));
}

// The report's picture of a large cured surface is clustered while the mesher makes it
// (keepView): the same clusters, mean positions, mean deviations and triangles as clustering
// every vertex of the whole mesh afterwards (brute force by cell below), untiled or in tiles
// (the halo's vertices join their owner's cluster), in a fraction of the triangles.
TEST_CASE("the clustered view made while meshing is the whole mesh clustered, tiled or not",
          "[validate]") {
    const geometry::Mesh part = boxPart();
    const auto grid = boxGrid();
    const double cell = 0.05;
    validate::StreamingCuredSurface kept(grid, DZ, 1.0, &part, BAND, "");
    kept.keepTriangles(true);
    feed(kept, grid, exposure::tileLayout(grid, 0, 2));
    const geometry::Mesh whole = kept.mesh();
    const std::vector<float>& deviations = kept.deviations();
    REQUIRE(deviations.size() == whole.vertices.size());

    // Brute force: every vertex into its cell; a triangle as the cells of its corners.
    using Key = std::array<int64_t, 3>;
    auto keyOf = [&](const glm::dvec3& p) {
        return Key{int64_t(std::floor(p.x / cell)), int64_t(std::floor(p.y / cell)),
                   int64_t(std::floor(p.z / cell))};
    };
    struct Sum {
        glm::dvec3 position{0.0};
        double deviation = 0;
        int count = 0;
    };
    std::map<Key, Sum> expected;
    for (size_t v = 0; v < whole.vertices.size(); ++v) {
        Sum& sum = expected[keyOf(whole.vertices[v])];
        sum.position += whole.vertices[v];
        sum.deviation += deviations[v];
        ++sum.count;
    }
    std::map<std::array<Key, 3>, int> expectedTriangles;
    for (const auto& t : whole.triangles) {
        const std::array<Key, 3> k{keyOf(whole.vertices[t[0]]), keyOf(whole.vertices[t[1]]),
                                   keyOf(whole.vertices[t[2]])};
        if (k[0] != k[1] && k[1] != k[2] && k[0] != k[2]) ++expectedTriangles[k];
    }
    size_t expectedCount = 0;
    for (const auto& entry : expectedTriangles) expectedCount += size_t(entry.second);

    for (int side : {0, 13}) {
        INFO("tile side " << side);
        validate::StreamingCuredSurface streamed(grid, DZ, 1.0, &part, BAND, "");
        streamed.keepView(cell);
        feed(streamed, grid, exposure::tileLayout(grid, side, 2));
        const validate::StreamingCuredSurface::View view = streamed.view();
        CHECK(view.cell == cell);
        CHECK(view.madeTriangles == kept.triangles());
        REQUIRE(view.mesh.vertices.size() == expected.size());
        REQUIRE(view.deviations.size() == expected.size());
        std::vector<Key> keys;
        int wrong = 0;
        for (size_t c = 0; c < view.mesh.vertices.size(); ++c) {
            // A cluster's mean lies in its cell (a box holds the mean of its points).
            keys.push_back(keyOf(view.mesh.vertices[c]));
            const auto it = expected.find(keys.back());
            if (it == expected.end()) {
                ++wrong;
                continue;
            }
            const Sum& sum = it->second;
            wrong += glm::length(view.mesh.vertices[c] - sum.position / double(sum.count)) > 1e-9 ||
                     std::abs(view.deviations[c] - sum.deviation / sum.count) > 1e-6;
        }
        CHECK(wrong == 0);
        std::map<std::array<Key, 3>, int> triangles;
        for (const auto& t : view.mesh.triangles) ++triangles[{keys[t[0]], keys[t[1]], keys[t[2]]}];
        CHECK(triangles == expectedTriangles);
        CHECK(view.mesh.triangles.size() == expectedCount);
        CHECK(view.mesh.triangles.size() * 4 < whole.triangles.size());
    }
    validate::StreamingCuredSurface late(grid, DZ, 1.0, &part, BAND, "");
    feed(late, grid, exposure::tileLayout(grid, 0, 2));
    CHECK_THROWS(late.keepView(cell));  // only from the first slice on
    CHECK_THROWS(validate::SurfaceClusters(0.0));
}

// What MPI ranks do with a job's tiles (pipeline/cluster_run.h): each tile into a fresh surface
// with an in-place STL, its saved state and STL triangles merged in the tiles' order into
// another surface, gives one surface fed every tile: the same counts, volume and statistics to
// the bit, and the same STL bytes; with a kept picture (figures or the 3D view), each tile's
// picture merged too (mergePicture) gives the same picture to the bit, clustered or with every
// triangle kept.
TEST_CASE("cured surfaces of single tiles merged in order are the surface of all tiles",
          "[validate]") {
    const geometry::Mesh part = boxPart();
    const auto grid = boxGrid();
    const auto tiles = exposure::tileLayout(grid, 13, 2);
    REQUIRE(tiles.size() > 3);
    const auto dir = std::filesystem::temp_directory_path();
    const std::string oneStl = (dir / "vpsim_merge_one.stl").string(),
                      mergedStl = (dir / "vpsim_merge_merged.stl").string(),
                      pictureFile = (dir / "vpsim_merge_picture.bin").string();
    for (double cell : {-1.0, 0.05, 0.0}) {  // -1: no picture
        INFO("cell " << cell);
        auto keepView = [&](validate::StreamingCuredSurface& surface) {
            if (cell >= 0) surface.keepView(cell);
        };
        validate::StreamingCuredSurface one(grid, DZ, 1.0, &part, BAND, oneStl);
        keepView(one);
        feed(one, grid, tiles);
        validate::StreamingCuredSurface merged(grid, DZ, 1.0, &part, BAND, mergedStl);
        keepView(merged);
        for (const exposure::Tile& tile : tiles) {
            const std::string tileStl = (dir / "vpsim_merge_tile.stl").string();
            nlohmann::json state;
            {
                validate::StreamingCuredSurface alone(
                    grid, DZ, 1.0, &part, BAND,
                    validate::StreamingCuredSurface::InPlaceStl{tileStl});
                keepView(alone);
                feed(alone, grid, {tile}, false);
                state = alone.saveState();
                BinaryStateWriter out(pictureFile);
                alone.savePicture(out);
                out.commit();
            }
            merged.mergeState(nlohmann::json::parse(state.dump()));
            // The triangles in uneven pieces, as the ranks stream them (cluster::streamToRoot).
            const std::string body = readFile(tileStl).substr(84);
            for (size_t at = 0; at < body.size(); at += 4099)
                merged.appendStl(body.substr(at, 4099));
            merged.mergePicture(BinaryStateReader(pictureFile));
        }
        merged.finish();
        CHECK(merged.triangles() == one.triangles());
        CHECK(merged.volume() == one.volume());
        CHECK(merged.statistics().toJson() == one.statistics().toJson());
        CHECK(readFile(mergedStl) == readFile(oneStl));
        const auto expected = one.view(), got = merged.view();
        CHECK(got.mesh.vertices == expected.mesh.vertices);
        CHECK(got.mesh.triangles == expected.mesh.triangles);
        CHECK(got.deviations == expected.deviations);
        CHECK(got.madeTriangles == expected.madeTriangles);
        if (cell >= 0) CHECK(expected.mesh.triangles.size() > 100);
    }
    // A picture of another view is refused, naming the file.
    validate::StreamingCuredSurface other(grid, DZ, 1.0, &part, BAND, "");
    other.keepView(0.1);
    CHECK_THROWS_WITH(other.mergePicture(BinaryStateReader(pictureFile)),
                      Catch::Contains("vpsim_merge_picture.bin"));
}

// A checkpoint of a run with figures (pipeline/checkpoint.h, PictureConsumers): the picture of
// the surface saved between two tiles (savePicture, binary) and continued in a fresh surface
// gives the uninterrupted picture exactly, clustered (keepView(cell)) or with every triangle
// kept (keepView(0), whose triangles refer to earlier tiles' vertices through the seams).
TEST_CASE("a surface's picture saved between tiles continues in another surface", "[validate]") {
    const geometry::Mesh part = boxPart();
    const auto grid = boxGrid();
    const auto tiles = exposure::tileLayout(grid, 13, 2);
    REQUIRE(tiles.size() > 3);
    const std::vector<exposure::Tile> first(tiles.begin(), tiles.begin() + 2),
        rest(tiles.begin() + 2, tiles.end());
    const std::string file =
        (std::filesystem::temp_directory_path() / "vpsim_surface_picture.bin").string();
    for (double cell : {0.05, 0.0}) {
        INFO("cell " << cell);
        validate::StreamingCuredSurface whole(grid, DZ, 1.0, &part, BAND, "");
        whole.keepView(cell);
        feed(whole, grid, tiles);
        nlohmann::json state;
        {
            validate::StreamingCuredSurface before(grid, DZ, 1.0, &part, BAND, "");
            before.keepView(cell);
            feed(before, grid, first, false);
            state = nlohmann::json::parse(before.saveState().dump());
            BinaryStateWriter out(file);
            before.savePicture(out);
            out.commit();
        }
        validate::StreamingCuredSurface after(grid, DZ, 1.0, &part, BAND, "");
        after.keepView(cell);
        after.restoreState(state);
        after.restorePicture(BinaryStateReader(file));
        feed(after, grid, rest);
        const auto expected = whole.view(), got = after.view();
        REQUIRE(got.mesh.vertices.size() == expected.mesh.vertices.size());
        CHECK(got.mesh.vertices == expected.mesh.vertices);
        CHECK(got.mesh.triangles == expected.mesh.triangles);
        CHECK(got.deviations == expected.deviations);
        CHECK(got.madeTriangles == expected.madeTriangles);
        CHECK(expected.mesh.triangles.size() > 100);

        // Another view's state is refused, naming the file.
        validate::StreamingCuredSurface other(grid, DZ, 1.0, &part, BAND, "");
        other.keepView(cell > 0 ? 2 * cell : 0.05);
        CHECK_THROWS_WITH(other.restorePicture(BinaryStateReader(file)),
                          Catch::Contains("vpsim_surface_picture.bin"));
    }
    // A file cut short, or not a state file: one error naming it.
    const std::string text = readFile(file);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << text.substr(0, text.size() / 2);
    CHECK_THROWS_WITH(BinaryStateReader(file),
                      Catch::Contains("cut short") && Catch::Contains("vpsim_surface_picture.bin"));
    std::ofstream(file, std::ios::binary | std::ios::trunc) << "solid x\n";
    CHECK_THROWS_WITH(BinaryStateReader(file), Catch::Contains("not a vpsim checkpoint"));
}
