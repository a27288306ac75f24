// Reference level set through OpenVDB: sign inside/outside, distance near the surface within a
// voxel of the exact distance, .vdb round trip, memory refusal and bad options.
#include <catch2/catch.hpp>

#include <cmath>

#include "test_util.h"
#include "vpsim/core/error.h"
#include "vpsim/geometry/level_set.h"
#include "vpsim/geometry/test_parts.h"

using namespace vpsim;
using namespace vpsim::geometry;

namespace {

LevelSetOptions voxels(double h) {
    LevelSetOptions o;
    o.voxelSize = h;
    return o;
}

}  // namespace

TEST_CASE("box level set: sign and distance near the faces", "[levelset]") {
    const double h = 0.1;
    const LevelSet ls = LevelSet::fromMesh(makeTestPart("box", test::sizeHeight(2.0, 2.0)),
                                           voxels(h));  // [-1,1]^2 x [0,2]
    CHECK(ls.voxelSize() == Approx(h));
    CHECK(ls.halfWidth() == Approx(3 * h).epsilon(1e-6));
    CHECK(ls.signedDistance({0, 0, 1}) < 0.0);  // deep inside: -background
    CHECK(ls.signedDistance({3, 0, 1}) > 0.0);  // far outside: +background
    // Tolerance one voxel (the brief's bound; trilinear interpolation of exact voxel distances
    // is much better on flat faces).
    for (double d : {-0.23, -0.12, -0.05, 0.0, 0.04, 0.13, 0.21}) {
        INFO("distance " << d);
        CHECK(ls.signedDistance({1.0 + d, 0.1, 1.0}) == Approx(d).margin(h));
        CHECK(ls.signedDistance({0.3, -0.2, 2.0 + d}) == Approx(d).margin(h));
        CHECK(ls.signedDistance({-0.4, 0.0, -d}) == Approx(d).margin(h));
    }
    // Batch sampling gives the same values as single queries.
    const std::vector<glm::dvec3> points{
        {1.05, 0.1, 1.0}, {0.0, 0.0, 1.0}, {0.3, -0.2, 2.02}, {5, 5, 5}};
    std::vector<float> values;
    ls.sample(points, values);
    REQUIRE(values.size() == points.size());
    for (size_t i = 0; i < points.size(); ++i)
        CHECK(values[i] == Approx(ls.signedDistance(points[i])).margin(1e-6));
    const Bounds b = ls.activeBounds();
    CHECK(b.lo.x == Approx(-1.0 - 3 * h).margin(h));
    CHECK(b.hi.z == Approx(2.0 + 3 * h).margin(h));
}

TEST_CASE("cylinder level set matches the distance to the curved side", "[levelset]") {
    const double h = 0.05;
    TestPartOptions o;
    o.segments = 256;  // polygon within 5 * (1 - cos(pi/256)) = 0.4 um of the circle
    const LevelSet ls = LevelSet::fromMesh(makeTestPart("cylinder", o), voxels(h));
    for (double angle : {0.1, 1.0, 2.5, 4.0}) {
        for (double d : {-0.1, -0.03, 0.02, 0.11}) {
            const double r = 5.0 + d;
            CHECK(ls.signedDistance({r * std::cos(angle), r * std::sin(angle), 5.0}) ==
                  Approx(d).margin(h));
        }
    }
}

TEST_CASE("level set saves to .vdb and loads back", "[levelset]") {
    const LevelSet ls =
        LevelSet::fromMesh(makeTestPart("l-shape", test::sizeHeight(4.0, 2.0)), voxels(0.1));
    const std::string path = test::tempPath("l.vdb");
    ls.save(path);
    const LevelSet back = LevelSet::load(path);
    CHECK(back.activeVoxelCount() == ls.activeVoxelCount());
    CHECK(back.signedDistance({1.05, -1.0, 1.0}) == Approx(ls.signedDistance({1.05, -1.0, 1.0})));
    CHECK_THROWS_AS(LevelSet::load(test::tempPath("missing.vdb")), InputError);
}

TEST_CASE("level set refuses bad options and oversized grids", "[levelset][bad-input]") {
    const Mesh box = makeTestPart("box");
    CHECK_THROWS_AS(LevelSet::fromMesh(box, voxels(0.0)), InputError);
    LevelSetOptions o = voxels(0.1);
    o.halfWidthVoxels = 0.5;
    CHECK_THROWS_AS(LevelSet::fromMesh(box, o), InputError);
    o = voxels(0.001);
    o.maxBytes = 1e8;
    CHECK_THROWS_AS(LevelSet::fromMesh(box, o), ResourceError);
}
