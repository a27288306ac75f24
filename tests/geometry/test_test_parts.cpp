// Test parts: closed-form volumes and areas, watertightness, bad options.
// Tolerance 1e-12 relative: the parts are built from exact coordinates (cylinder: cos/sin in
// double), so only summation rounding remains.
#include <catch2/catch.hpp>

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/geometry/mesh_check.h"
#include "vpsim/geometry/test_parts.h"

using namespace vpsim;
using namespace vpsim::geometry;

namespace {
constexpr double PI = 3.14159265358979323846;
constexpr double EXACT = 1e-12;
}  // namespace

TEST_CASE("test part volumes match closed forms", "[parts]") {
    CHECK(makeTestPart("box").volume() == Approx(1000.0).epsilon(EXACT));
    // Frustum: h/3 (a^2 + ab + b^2) with a = 10, b = 5, h = 10.
    CHECK(makeTestPart("tapered").volume() ==
          Approx(10.0 / 3.0 * (100.0 + 50.0 + 25.0)).epsilon(EXACT));
    CHECK(makeTestPart("bottom-narrow").volume() == Approx(10.0 / 3.0 * 175.0).epsilon(EXACT));
    CHECK(makeTestPart("l-shape").volume() == Approx(750.0).epsilon(EXACT));
    // 10 x 5 x 11 block minus holes 3 x 3 and 1.5 x 1.5 through 5 mm.
    CHECK(makeTestPart("holes").volume() == Approx(550.0 - 5.0 * (9.0 + 2.25)).epsilon(EXACT));
    // Column 4 x 10, ledges 6 x 3 and 6 x 1, all 5 deep.
    CHECK(makeTestPart("overhangs").volume() == Approx(5.0 * (40.0 + 18.0 + 6.0)).epsilon(EXACT));
    TestPartOptions pillars;
    pillars.count = 5;
    CHECK(makeTestPart("pillars", pillars).volume() == Approx(5.0 * 1.0 * 2.0).epsilon(EXACT));
    TestPartOptions cylinder;
    cylinder.segments = 12;
    CHECK(makeTestPart("cylinder", cylinder).volume() ==
          Approx(0.5 * 12 * 25.0 * std::sin(2.0 * PI / 12) * 10.0).epsilon(EXACT));
}

TEST_CASE("test part options change the shape", "[parts]") {
    TestPartOptions o;
    o.size = 4.0;
    o.topSize = 1.0;
    o.height = 3.0;
    const Mesh frustum = makeTestPart("tapered", o);
    CHECK(frustum.volume() == Approx(1.0 * (16.0 + 4.0 + 1.0)).epsilon(EXACT));
    const Bounds b = frustum.bounds();
    CHECK(b.lo.x == -2.0);
    CHECK(b.hi.z == 3.0);
    TestPartOptions p;
    p.count = 9;
    p.spacing = 2.0;
    Mesh pillars = makeTestPart("pillars", p);
    const MeshReport report = checkMesh(pillars, "pillars");
    CHECK(report.shells == 9);
    CHECK(pillars.bounds().size().x == Approx(2.0 * 2.0 + 1.0));
}

TEST_CASE("bad test part options are clear errors", "[parts][bad-input]") {
    TestPartOptions o;
    CHECK_THROWS_WITH(makeTestPart("sphere"),
                      Catch::Matchers::Contains("unknown test part 'sphere'"));
    o.size = -1.0;
    CHECK_THROWS_AS(makeTestPart("box", o), InputError);
    o.size = 3.0;
    CHECK_THROWS_WITH(makeTestPart("holes", o), Catch::Matchers::Contains("size > 4"));
    TestPartOptions c;
    c.segments = 2;
    CHECK_THROWS_AS(makeTestPart("cylinder", c), InputError);
    TestPartOptions p;
    p.spacing = 0.5;
    CHECK_THROWS_WITH(makeTestPart("pillars", p), Catch::Matchers::Contains("spacing"));
    CHECK_THROWS_WITH(makeTestPart("box", p),
                      Catch::Matchers::Contains("option spacing does not apply"));
    TestPartOptions h;
    h.height = 5.0;
    CHECK_THROWS_WITH(makeTestPart("holes", h), Catch::Matchers::Contains("fixed by seed 001"));
}
