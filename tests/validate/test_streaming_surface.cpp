#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "vpsim/exposure/dose_volume.h"
#include "vpsim/geometry/mesh_distance.h"
#include "vpsim/geometry/test_parts.h"
#include "vpsim/validate/streaming_surface.h"

using namespace vpsim;

namespace {

/// Slices of a smooth dose field 2 exp(-(r/R)^2) about `centre`, top down: cured (dose >= 1)
/// inside the sphere of radius R sqrt(ln 2).
/// With `scribble`, each slice's buffer is overwritten as soon as add() returns (the surface
/// makes its layer in the background, from its own copy) and the vertices are read between
/// slices (they wait for that layer).
validate::StreamingCuredSurface& feedSphere(validate::StreamingCuredSurface& surface,
                                            const exposure::ExposureGrid& grid, double dz,
                                            int slices, glm::dvec3 centre, double R,
                                            bool scribble = false,
                                            std::vector<size_t>* vertexCounts = nullptr) {
    exposure::SurfaceGrid values = grid.surface();
    for (int k = slices - 1; k >= 0; --k) {
        const double z = (k + 0.5) * dz;
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i) {
                const glm::dvec3 d = glm::dvec3(values.centreX(i), values.centreY(j), z) - centre;
                values.at(i, j) = float(2.0 * std::exp(-glm::dot(d, d) / (R * R)));
            }
        surface.add({0, slices - 1 - k, z, &values});
        if (scribble) std::fill(values.values.begin(), values.values.end(), 1e30f);
        if (vertexCounts) vertexCounts->push_back(surface.vertices().size());
    }
    surface.finish();
    return surface;
}

}  // namespace

// The streamed surface-nets mesh of a sphere is closed and consistently oriented (every directed
// edge once, its reverse once), encloses the sphere's volume to 1% (the mesh is within a small
// part of a voxel of the iso-surface: a 0.3 mm sphere at 20 um voxels), and its signed
// deviation from a reference sphere mesh sits near zero.
TEST_CASE("the streamed cured surface of a sphere is closed and right-sized", "[validate]") {
    const double R = 0.3 / std::sqrt(std::log(2.0)), radius = 0.3, dz = 0.02;
    const glm::dvec3 centre(0.5, 0.5, 0.5);
    auto grid = exposure::ExposureGrid::covering(0, 0, 1, 1, 0.0, 0.02, 1);
    validate::StreamingCuredSurface surface(grid, dz, 1.0, nullptr, 0.1, "");
    surface.keepTriangles(true);
    feedSphere(surface, grid, dz, 50, centre, R);
    const geometry::Mesh mesh = surface.mesh();
    REQUIRE(mesh.triangles.size() == surface.triangles());
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    int bad = 0;
    for (const auto& [edge, count] : directed)
        bad += count != 1 || directed.count({edge.second, edge.first}) == 0;
    CHECK(bad == 0);
    const double exact = 4.0 / 3.0 * M_PI * radius * radius * radius;
    CHECK(surface.volume() == Approx(exact).epsilon(0.01));
    CHECK(mesh.volume() == Approx(surface.volume()).epsilon(1e-5));
    for (const auto& v : surface.vertices())
        CHECK(std::abs(glm::length(glm::dvec3(v) - centre) - radius) < 0.25 * 0.02);
}

// add() copies the slice before it returns and makes the layer in the background: a slice buffer
// overwritten at once changes nothing, and every call between slices sees the finished layer
// (the same vertices as a surface fed slice by slice and read the same way).
TEST_CASE("the streamed cured surface owns its slices once add() returns", "[validate]") {
    const double R = 0.3 / std::sqrt(std::log(2.0)), dz = 0.02;
    auto grid = exposure::ExposureGrid::covering(0, 0, 1, 1, 0.0, 0.02, 1);
    validate::StreamingCuredSurface clean(grid, dz, 1.0, nullptr, 0.1, "");
    validate::StreamingCuredSurface scribbled(grid, dz, 1.0, nullptr, 0.1, "");
    std::vector<size_t> cleanCounts, scribbledCounts;
    for (auto* surface : {&clean, &scribbled}) surface->keepTriangles(true);
    feedSphere(clean, grid, dz, 50, {0.5, 0.5, 0.5}, R, false, &cleanCounts);
    feedSphere(scribbled, grid, dz, 50, {0.5, 0.5, 0.5}, R, true, &scribbledCounts);
    CHECK(scribbledCounts == cleanCounts);
    REQUIRE(cleanCounts.back() > 0);
    CHECK(scribbled.triangles() == clean.triangles());
    CHECK(scribbled.volume() == clean.volume());
    CHECK(scribbled.mesh().triangles == clean.mesh().triangles);
    CHECK(scribbled.vertices() == clean.vertices());
}

// The exact signed distance through the BVH against brute force on a box: sign by the
// pseudonormals at faces, edges and corners.
TEST_CASE("the mesh distance is exact and signed at faces, edges and corners", "[validate]") {
    geometry::TestPartOptions options;
    options.size = 2.0;
    options.height = 1.0;
    const geometry::MeshDistance distance(geometry::makeTestPart("box", options));
    // The box [-1, 1] x [-1, 1] x [0, 1]: exact signed distance in closed form.
    auto exact = [](glm::dvec3 p) {
        const glm::dvec3 q = glm::abs(p - glm::dvec3(0, 0, 0.5)) - glm::dvec3(1, 1, 0.5);
        const double outside = glm::length(glm::max(q, glm::dvec3(0.0)));
        return outside + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
    };
    uint64_t state = 12345;
    auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) / double(1ull << 53);
    };
    uint32_t hint = geometry::MeshDistance::NO_HINT;  // the last point's nearest triangle
    for (int n = 0; n < 20000; ++n) {
        const glm::dvec3 p(3 * uniform() - 1.5, 3 * uniform() - 1.5, 2 * uniform() - 0.5);
        CHECK(distance.signedDistance(p) == Approx(exact(p)).margin(1e-12));
        // Seeded with a triangle that is mostly not the nearest: the same distance.
        CHECK(distance.signedDistance(p, hint) == Approx(exact(p)).margin(1e-12));
        CHECK(hint != geometry::MeshDistance::NO_HINT);
    }
    // Corners and edges approached from outside along their diagonals.
    CHECK(distance.signedDistance({1.1, 1.1, 1.1}) == Approx(std::sqrt(0.03)));
    CHECK(distance.signedDistance({1.1, 0.0, -0.1}) == Approx(std::sqrt(0.02)));
}

// The nearest-triangle proofs skip the search only where it would find the same triangle: patches
// of rows of points near the surface, 10 um apart (as the cured surface's vertices come), on
// parts with flat faces split along diagonals, concave corners and a faceted cylinder, and rows
// along a triangle's edge exactly (ties between triangles), give the search's distance and
// triangle to the bit; on the 10 mm block and L most points need no search (about 1 in 20 and
// 1 in 15 here; small pillars and facets need more).
TEST_CASE("nearest-triangle proofs give the search's distance to the bit", "[validate]") {
    geometry::TestPartOptions options;
    options.size = 10.0;  // the bench block's
    options.height = 5.0;
    uint64_t state = 777;
    auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) / double(1ull << 53);
    };
    for (const char* name : {"box", "l-shape", "pillars", "cylinder"}) {
        INFO(name);
        const geometry::Mesh mesh = geometry::makeTestPart(
            name, std::string(name) == "pillars" ? geometry::TestPartOptions() : options);
        const geometry::MeshDistance distance(mesh);
        geometry::MeshDistance::NearestProofs proofs;
        uint32_t searched = geometry::MeshDistance::NO_HINT, proved = searched;
        int points = 0, differ = 0;
        auto query = [&](const glm::dvec3& p) {
            const double expected = distance.signedDistance(p, searched);
            const double got = distance.signedDistance(p, proved, proofs);
            differ += got != expected || proved != searched;
            ++points;
        };
        auto randomTriangle = [&] {
            const auto& tri = mesh.triangles[size_t(uniform() * double(mesh.triangles.size()))];
            return std::array<glm::dvec3, 3>{mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                             mesh.vertices[tri[2]]};
        };
        for (int patch = 0; patch < 100; ++patch) {
            const auto [a, b, c] = randomTriangle();
            const glm::dvec3 normal = glm::normalize(glm::cross(b - a, c - a));
            // Rows along one direction in the plane, the next row beside it, within 20 um of it.
            const glm::dvec3 along = glm::normalize(glm::cross(
                normal, std::abs(normal.x) < 0.5 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
            const glm::dvec3 across = glm::cross(normal, along);
            const double u = uniform(), v = uniform() * (1 - u);
            const glm::dvec3 start = a + u * (b - a) + v * (c - a);
            for (int row = 0; row < 10; ++row)
                for (int k = 0; k < 20; ++k)
                    query(start + 0.01 * (double(k) * along + double(row) * across) +
                          (0.04 * uniform() - 0.02) * normal);
        }
        const uint64_t patchPoints = uint64_t(points), patchSearches = proofs.searches;
        for (int edge = 0; edge < 100; ++edge) {  // exactly on edges: ties
            const auto [a, b, c] = randomTriangle();
            for (int k = 0; k <= 20; ++k) query(a + (0.05 * k) * (b - a));
        }
        CHECK(differ == 0);
        if (std::string(name) == "box" || std::string(name) == "l-shape")
            CHECK(patchSearches < patchPoints / 4);
    }
}

// Inside a concave corner (the L-shape's) the sign follows the part, not the nearest face alone.
TEST_CASE("the mesh distance is signed right beside a concave corner", "[validate]") {
    geometry::TestPartOptions options;
    options.size = 2.0;
    options.height = 1.0;
    const geometry::Mesh l = geometry::makeTestPart("l-shape", options);
    const geometry::MeshDistance distance(l);
    // The L footprint [0,2]x[0,1] + [0,1]x[1,2], centred: shifted by (-1, -1).
    auto insideL = [](double x, double y) {
        x += 1, y += 1;
        return (x > 0 && x < 2 && y > 0 && y < 1) || (x > 0 && x < 1 && y > 0 && y < 2);
    };
    for (double x = -1.2; x <= 1.2; x += 0.05)
        for (double y = -1.2; y <= 1.2; y += 0.05) {
            const double d = distance.signedDistance({x, y, 0.5});
            if (std::abs(d) < 1e-9) continue;
            INFO("x " << x << " y " << y << " d " << d);
            CHECK((d < 0) == insideL(x, y));
        }
}
