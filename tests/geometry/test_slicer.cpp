// Slicing against analytic cross-sections of the test parts, plane-through-vertex robustness,
// orientation of outers and holes.
//
// Tolerance: slices are rounded to Clipper's 1 nm grid, so an area may differ from the exact
// value by at most (perimeter x 1 nm) and a perimeter by (vertex count x 1.5 nm); we allow
// perimeter x 1e-6 mm for areas and 1e-5 mm + 1e-9 relative for perimeters.
#include <catch2/catch.hpp>

#include <cmath>

#include <glm/mat3x3.hpp>

#include "vpsim/core/error.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/geometry/test_parts.h"

using namespace vpsim;
using namespace vpsim::geometry;

namespace {

constexpr double PI = 3.14159265358979323846;

void checkArea(const PolygonSet& region, double expectedArea, double expectedPerimeter) {
    CHECK(std::abs(region.area() - expectedArea) <= expectedPerimeter * 1e-6 + 1e-12);
    CHECK(region.perimeter() == Approx(expectedPerimeter).margin(1e-5).epsilon(1e-9));
}

void checkOrientation(const PolygonSet& region) {
    for (const auto& part : region.parts()) {
        CHECK(signedArea(part.outer) > 0.0);  // outer contours CCW from +z
        for (const auto& hole : part.holes) CHECK(signedArea(hole) < 0.0);
    }
}

SliceOptions layers(double thickness, double plane = 0.5) {
    SliceOptions o;
    o.layerThickness = thickness;
    o.planePosition = plane;
    return o;
}

}  // namespace

TEST_CASE("layer count and plane positions", "[slice]") {
    const Mesh box = makeTestPart("box");
    CHECK(layerCount(box, layers(0.05)) == 200);  // 10 mm / 50 um, no float sliver layer
    CHECK(layerCount(box, layers(0.025)) == 400);
    CHECK(layerCount(box, layers(3.0)) == 4);
    // A float32 STL's 0.2 mm (0.200000003 mm) in 50 um layers is 4 layers, not 5.
    Mesh thin = box;
    for (auto& v : thin.vertices) v.z = double(float(v.z * 0.02));
    CHECK(layerCount(thin, layers(0.05)) == 4);
    CHECK(layerCount(thin, layers(0.0499)) == 5);
    const auto slices = sliceMesh(box, layers(0.05), {0, 199});
    REQUIRE(slices.size() == 2);
    CHECK(slices[0].z == Approx(0.025).margin(1e-15));
    CHECK(slices[1].zBottom == Approx(9.95).margin(1e-12));
    CHECK_THROWS_AS(sliceMesh(box, layers(0.05), {200}), InputError);
    CHECK_THROWS_AS(sliceMesh(box, layers(0.0)), InputError);
    CHECK_THROWS_AS(sliceMesh(box, layers(0.05, 1.5)), InputError);
}

TEST_CASE("frustum cross-sections follow the linear taper", "[slice]") {
    for (const std::string name : {"tapered", "bottom-narrow"}) {
        const Mesh part = makeTestPart(name);  // sides 10 and 5 mm, height 10 mm
        for (const auto& layer : sliceMesh(part, layers(0.1))) {
            const double t = layer.z / 10.0;
            const double side = name == "tapered" ? 10.0 + (5.0 - 10.0) * t : 5.0 + 5.0 * t;
            INFO(name << " z = " << layer.z);
            REQUIRE(layer.region.outerCount() == 1);
            CHECK(layer.region.holeCount() == 0);
            checkArea(layer.region, side * side, 4.0 * side);
            checkOrientation(layer.region);
        }
    }
}

TEST_CASE("cylinder slices are exactly the N-gon", "[slice]") {
    for (int n : {3, 7, 64, 500}) {
        TestPartOptions o;
        o.segments = n;
        const Mesh part = makeTestPart("cylinder", o);  // radius 5
        const double area = 0.5 * n * 25.0 * std::sin(2.0 * PI / n);
        const double perimeter = 2.0 * n * 5.0 * std::sin(PI / n);
        for (const auto& layer : sliceMesh(part, layers(1.0))) {
            INFO("segments " << n << " z " << layer.z);
            REQUIRE(layer.region.outerCount() == 1);
            checkArea(layer.region, area, perimeter);
            CHECK(layer.region.parts()[0].outer.size() >= size_t(n));  // + points on chords
        }
    }
}

TEST_CASE("holes part: the two through-holes split the layers at the right heights", "[slice]") {
    const Mesh part =
        makeTestPart("holes");  // 10 x 5 x 11, holes 3 mm (z 2..5) and 1.5 mm (z 7..8.5)
    const auto slices = sliceMesh(part, layers(0.05));
    REQUIRE(slices.size() == 220);
    int bottomHoleLayers = 0, topHoleLayers = 0;
    for (const auto& layer : slices) {
        const bool inBottom = layer.z > 2.0 && layer.z<5.0, inTop = layer.z> 7.0 && layer.z < 8.5;
        INFO("z = " << layer.z);
        const double width = inBottom ? 7.0 : inTop ? 8.5 : 10.0;
        CHECK(layer.region.outerCount() == (inBottom || inTop ? 2u : 1u));
        checkArea(layer.region, width * 5.0,
                  inBottom || inTop ? 2.0 * (2 * width / 2 + 10.0) : 30.0);
        bottomHoleLayers += inBottom;
        topHoleLayers += inTop;
    }
    CHECK(bottomHoleLayers == 60);  // 3 mm / 50 um
    CHECK(topHoleLayers == 30);     // 1.5 mm / 50 um
}

TEST_CASE("overhangs part: ledges 1 mm and 3 mm thick at their heights", "[slice]") {
    const Mesh part = makeTestPart("overhangs");  // column 4 mm, ledges 6 mm long, depth 5
    for (const auto& layer : sliceMesh(part, layers(0.05))) {
        const bool ledge = (layer.z > 3.0 && layer.z < 4.0) || (layer.z > 7.0 && layer.z < 10.0);
        INFO("z = " << layer.z);
        CHECK(layer.region.outerCount() == 1u);
        checkArea(layer.region, ledge ? 50.0 : 20.0, ledge ? 30.0 : 18.0);
    }
}

TEST_CASE("l-shape keeps its sharp convex and concave corners", "[slice]") {
    const PolygonSet region = sliceAt(makeTestPart("l-shape"), 5.0);
    REQUIRE(region.outerCount() == 1);
    checkArea(region, 75.0, 40.0);
    checkOrientation(region);
    CHECK(region.parts()[0].outer.size() == 6);   // collinear grid points removed, 6 corners left
    CHECK(region.contains({2.0, 2.0}) == false);  // the notch
    CHECK(region.contains({-2.0, 2.0}));
}

TEST_CASE("a vertical hole is a clockwise hole; an island inside it is another outer", "[slice]") {
    // 5 x 5 cells: ring of solid, empty ring, solid centre cell.
    std::vector<double> xs{0, 1, 2, 3, 4, 5};
    std::vector<char> filled(25, 1);
    for (int j = 1; j <= 3; ++j) {
        for (int i = 1; i <= 3; ++i) filled[i + 5 * j] = (i == 2 && j == 2);
    }
    const Mesh part = makeCellMesh(xs, xs, {0.0, 1.0}, filled);
    const PolygonSet region = sliceAt(part, 0.5);
    CHECK(region.outerCount() == 2);
    CHECK(region.holeCount() == 1);
    checkOrientation(region);
    checkArea(region, 25.0 - 9.0 + 1.0, 20.0 + 12.0 + 4.0);
}

TEST_CASE("planes exactly through vertices and horizontal faces", "[slice][robust]") {
    const Mesh holes = makeTestPart("holes");
    // planePosition 0 with 0.5 mm layers puts planes exactly on z = 2, 5, 7, 8.5 (hole faces);
    // the section is the one just above the plane.
    for (const auto& layer : sliceMesh(holes, layers(0.5, 0.0))) {
        const bool inHole = (layer.z >= 2.0 && layer.z < 5.0) || (layer.z >= 7.0 && layer.z < 8.5);
        INFO("z = " << layer.z);
        CHECK(layer.region.outerCount() == (inHole ? 2u : 1u));
    }
    // planePosition 1: planes on the same faces, section just below.
    for (const auto& layer : sliceMesh(holes, layers(0.5, 1.0))) {
        const bool inHole = (layer.z > 2.0 && layer.z <= 5.0) || (layer.z > 7.0 && layer.z <= 8.5);
        INFO("z = " << layer.z);
        CHECK(layer.region.outerCount() == (inHole ? 2u : 1u));
    }
    // Bottom and top faces: the first layer's plane at z = 0 and the last at z = 11 are full.
    CHECK(sliceMesh(holes, layers(0.5, 0.0)).front().region.area() == Approx(50.0).epsilon(1e-9));
    CHECK(sliceMesh(holes, layers(0.5, 1.0)).back().region.area() == Approx(50.0).epsilon(1e-9));
    CHECK(sliceAt(holes, 0.0, false).empty());
    CHECK(sliceAt(holes, 11.0, true).empty());

    // Octahedron: four vertices exactly on z = 0, no horizontal face; both sides agree.
    Mesh octa;
    octa.vertices = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (uint32_t k = 0; k < 4; ++k) {
        octa.triangles.push_back({k, (k + 1) % 4, 4});
        octa.triangles.push_back({(k + 1) % 4, k, 5});
    }
    for (bool up : {true, false}) {
        const PolygonSet s = sliceAt(octa, 0.0, up);
        REQUIRE(s.outerCount() == 1);
        CHECK(s.area() == Approx(2.0).epsilon(1e-12));
        checkOrientation(s);
    }
    // Frustum planes through its top ring (z = 10) and bottom ring.
    const Mesh frustum = makeTestPart("tapered");
    CHECK(sliceAt(frustum, 0.0, true).area() == Approx(100.0).epsilon(1e-12));
    CHECK(sliceAt(frustum, 10.0, false).area() == Approx(25.0).epsilon(1e-9));
}

TEST_CASE("pillars give one outer per pillar", "[slice]") {
    TestPartOptions o;
    o.count = 7;
    const auto slices = sliceMesh(makeTestPart("pillars", o), layers(0.5));
    REQUIRE(slices.size() == 4);
    for (const auto& layer : slices) {
        CHECK(layer.region.outerCount() == 7);
        checkArea(layer.region, 7.0, 28.0);
        checkOrientation(layer.region);
    }
}

TEST_CASE("slicing an open mesh is a clear error", "[slice][bad-input]") {
    Mesh box = makeTestPart("box");
    box.triangles.erase(box.triangles.begin() + 4);  // a side face triangle
    CHECK_THROWS_WITH(sliceMesh(box, layers(1.0)), Catch::Matchers::Contains("does not close"));
}

TEST_CASE("zStart shifts the layer grid", "[slice]") {
    SliceOptions o = layers(1.0);
    o.zStart = -0.5;  // layers [-0.5, 0.5], [0.5, 1.5] ... planes at 0, 1, ..., 10
    const Mesh box = makeTestPart("box");
    CHECK(layerCount(box, o) == 11);
    const auto slices = sliceMesh(box, o);
    CHECK(slices.front().z == 0.0);
    CHECK(slices.front().region.area() ==
          Approx(100.0));  // plane on the bottom face, section above
    CHECK(slices.back().z == 10.0);
    CHECK(slices.back().region.empty());  // plane on the top face, section above
}

TEST_CASE("a tilted cube in general position: every layer closes and areas integrate to the volume",
          "[slice]") {
    // Rotation by fixed angles (no vertex on a plane, edges at all slopes). The midpoint rule on
    // the piecewise-quadratic area A(z) errs by at most t^2/24 * integral |A''| (well below
    // 1e-4 of the volume at t = 20 um), so a 1e-4 relative tolerance checks the slices.
    Mesh cube = makeTestPart("box");
    const double a = 0.3, b = 0.7, c = 1.1;
    const glm::dmat3 rx(1, 0, 0, 0, std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a));
    const glm::dmat3 ry(std::cos(b), 0, -std::sin(b), 0, 1, 0, std::sin(b), 0, std::cos(b));
    const glm::dmat3 rz(std::cos(c), std::sin(c), 0, -std::sin(c), std::cos(c), 0, 0, 0, 1);
    for (auto& v : cube.vertices) v = rz * ry * rx * v;
    const double t = 0.02;
    double volume = 0.0;
    for (const auto& layer : sliceMesh(cube, layers(t))) {
        REQUIRE(layer.region.outerCount() <= 1);
        checkOrientation(layer.region);
        volume += layer.region.area() * t;
    }
    CHECK(volume == Approx(1000.0).epsilon(1e-4));
}
