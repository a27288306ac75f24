#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "vpsim/cure/threshold_law.h"

using namespace vpsim;

// The float threshold that the slice loops compare against must decide exactly as isCured does
// in double: checked on the floats next to the critical dose (where rounding decides) and on
// random doses, for critical doses that a float holds exactly and ones it does not.
TEST_CASE("the float cure threshold decides exactly as isCured", "[cure]") {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (double ec : {0.1, 0.125, 1.0 / 3.0, 0.0999999999, 7.3e-5, 12.0}) {
        const cure::ThresholdLaw law(ec);
        const float at = law.curedFloatThreshold();
        CHECK(double(at) >= ec);
        CHECK(double(std::nextafter(at, 0.0f)) < ec);
        float d = float(ec);
        for (int k = 0; k < 40; ++k) d = std::nextafter(d, 0.0f);
        for (int k = 0; k < 80; ++k, d = std::nextafter(d, INFINITY))
            CHECK((d >= at) == law.isCured(d));
        for (int k = 0; k < 2000; ++k) {
            const float dose = float(2.0 * ec * unit(random));
            CHECK((dose >= at) == law.isCured(dose));
        }
        CHECK_FALSE(std::nanf("") >= at);  // NaN is not cured, as isCured says
    }
}
