// Particles index-matched to the resin do not scatter: a clear message, not a phase-table error.
#include <catch2/catch.hpp>

#include "vpsim/core/error.h"
#include "vpsim/optics/slurry.h"

using namespace vpsim;
using namespace vpsim::optics;
using Catch::Matchers::Contains;

TEST_CASE("particle index equal to the resin's is refused as non-scattering", "[optics][slurry]") {
    SlurrySpec s;
    s.wavelength = 405e-6;
    s.resinIndex = 1.45;
    s.resinPenetrationDepth = 0.119;
    s.particleIndex = {1.45, 0.0};
    s.radius = 2.5e-3;
    s.volumeFraction = 0.5;
    CHECK_THROWS_WITH(computeSlurryOptics(s), Contains("do not scatter"));
    s.particleIndex = {1.46, 0.0};  // a small contrast still scatters
    const SlurryOptics o = computeSlurryOptics(s);
    CHECK(o.medium.mus > 0.0);
}
