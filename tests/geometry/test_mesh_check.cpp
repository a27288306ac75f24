// Mesh checks and repairs: each defect gives its documented repair or one clear InputError.
#include <catch2/catch.hpp>

#include <algorithm>

#include "test_util.h"
#include "vpsim/core/error.h"
#include "vpsim/geometry/mesh_check.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/geometry/test_parts.h"

using namespace vpsim;
using namespace vpsim::geometry;
using Catch::Matchers::Contains;

namespace {

constexpr double EXACT = 1e-12;  // volumes of meshes with float-exact coordinates

/// Writes a mesh as a binary STL soup and reads it back through readStl().
Mesh roundTrip(const Mesh& mesh, const std::string& name, MeshReport& report) {
    const std::string path = test::tempPath(name);
    test::writeBytes(path, test::binaryStlBytes(mesh));
    return readStl(path, {}, &report);
}

std::string errorOf(const Mesh& mesh, const std::string& name) {
    try {
        MeshReport report;
        roundTrip(mesh, name, report);
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

}  // namespace

TEST_CASE("every test part passes the checks without repairs", "[mesh]") {
    for (const auto& name : testPartNames()) {
        Mesh part = makeTestPart(name);
        const MeshReport report = checkMesh(part, name);
        INFO(name);
        CHECK(report.ok());
        CHECK(report.repairs.empty());
        CHECK(report.openEdges == 0);
        CHECK(report.volume > 0.0);
    }
}

TEST_CASE("degenerate triangles are dropped and reported", "[mesh][repair]") {
    Mesh box = makeTestPart("box");
    box.triangles.push_back({0, 0, 1});  // repeats a vertex: zero area, cancels its own edge uses
    MeshReport report;
    const Mesh repaired = roundTrip(box, "degenerate.stl", report);
    CHECK(report.degenerateTrianglesDropped == 1);
    REQUIRE(report.repairs.size() == 1);
    CHECK_THAT(report.repairs[0], Contains("dropped 1 zero-area"));
    CHECK(repaired.triangles.size() == 12);
    CHECK(repaired.volume() == Approx(1000.0).epsilon(EXACT));
}

TEST_CASE("flipped faces are reoriented by flood fill", "[mesh][repair]") {
    Mesh box = makeTestPart("box");
    std::swap(box.triangles[2][0], box.triangles[2][1]);
    std::swap(box.triangles[7][0], box.triangles[7][1]);
    MeshReport report;
    const Mesh repaired = roundTrip(box, "flipped.stl", report);
    CHECK(report.trianglesReoriented == 2);
    CHECK(report.shellsFlipped == 0);
    CHECK(repaired.volume() == Approx(1000.0).epsilon(EXACT));
}

TEST_CASE("an inside-out mesh is turned around", "[mesh][repair]") {
    Mesh cylinder = makeTestPart("cylinder");
    const double volume = cylinder.volume();
    for (auto& t : cylinder.triangles) std::swap(t[1], t[2]);
    MeshReport report;
    const Mesh repaired = roundTrip(cylinder, "inside_out.stl", report);
    CHECK(report.shellsFlipped == 1);
    CHECK(report.trianglesReoriented == 0);
    // Float STL coordinates of cos/sin: relative 1e-7 (float epsilon) on the volume.
    CHECK(repaired.volume() == Approx(volume).epsilon(1e-6));
}

TEST_CASE("a cavity shell is oriented inward, whatever its input orientation", "[mesh][repair]") {
    Mesh outer = makeTestPart("box");                                    // 10 mm cube
    const Mesh inner = makeTestPart("box", test::sizeHeight(4.0, 4.0));  // 4 mm cube inside it
    Mesh part = outer;
    Mesh innerShifted = inner;
    innerShifted.translate({0.0, 0.0, 3.0});
    part.append(innerShifted);  // cavity with outward normals: wrong, must be flipped
    MeshReport report;
    Mesh repaired = roundTrip(part, "cavity.stl", report);
    CHECK(report.shells == 2);
    CHECK(report.shellsFlipped == 1);
    CHECK(repaired.volume() == Approx(1000.0 - 64.0).epsilon(EXACT));
    // Now correctly oriented: checking again changes nothing.
    const MeshReport again = checkMesh(repaired, "cavity");
    CHECK(again.repairs.empty());
}

TEST_CASE("an open mesh is a clear error with the count and a location", "[mesh][bad-input]") {
    Mesh box = makeTestPart("box");
    box.triangles.pop_back();
    CHECK_THAT(errorOf(box, "open.stl"),
               Contains("open.stl: 3 open edges (mesh is not watertight), first near (") &&
                   Contains(") mm"));
}

TEST_CASE("non-manifold edges are a clear error", "[mesh][bad-input]") {
    // Two cubes sharing one edge only: that edge has four triangles.
    Mesh part = makeTestPart("box", test::sizeHeight(1.0, 1.0));
    Mesh other = part;
    other.translate({1.0, 1.0, 0.0});
    part.append(other);
    CHECK_THAT(errorOf(part, "nonmanifold.stl"), Contains("1 non-manifold edges"));
}

TEST_CASE("a mesh with no volume is rejected", "[mesh][bad-input]") {
    // Two triangles back to back: closed and manifold, but enclosing nothing.
    Mesh flat;
    flat.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
    flat.triangles = {{0, 1, 2}, {0, 2, 1}};
    CHECK_THAT(errorOf(flat, "flat.stl"), Contains("flat.stl: mesh encloses no volume"));
}

TEST_CASE("with repair off, repairable defects are reported as problems", "[mesh]") {
    Mesh box = makeTestPart("box");
    for (auto& t : box.triangles) std::swap(t[1], t[2]);
    MeshCheckOptions options;
    options.repair = false;
    options.throwOnProblem = false;
    const MeshReport report = checkMesh(box, "box", options);
    CHECK_FALSE(report.ok());
    CHECK_THAT(report.problems.at(0), Contains("inside-out"));
    CHECK(report.toJson()["ok"] == false);
}

TEST_CASE("overlapping shells (a self-intersecting union) both stay outward", "[mesh]") {
    // An L-shape and a 2 x 2 x 4 box straddling the edge of its notch: the box's bounding box lies
    // inside the L's and one probe point is inside the L, but the box is not a cavity.
    Mesh part = makeTestPart("l-shape");
    Mesh other = makeTestPart("box", test::sizeHeight(2.0, 4.0));
    other.translate({2.0, 0.0, 2.0});  // x 1..3, y -1..1, z 2..6; the notch is x > 0, y > 0
    part.append(other);
    MeshReport report;
    const Mesh checked = roundTrip(part, "overlap.stl", report);
    CHECK(report.shells == 2);
    CHECK(report.shellsFlipped == 0);
    CHECK(report.repairs.empty());
    // Slices are the union: 75 + 4 - 2 (overlap x 1..3, y -1..0).
    const PolygonSet section = sliceAt(checked, 4.0);
    CHECK(section.area() == Approx(77.0).epsilon(1e-9));
    CHECK(section.outerCount() == 1);
}
