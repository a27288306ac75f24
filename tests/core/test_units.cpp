#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/units.h"

using namespace vpsim;
using Catch::Matchers::Contains;

// Tolerance: conversions are a product of a few decimal factors, so 1e-12 relative.
TEST_CASE("quantities convert to base units mm s mJ", "[core][units]") {
    CHECK(parseQuantity("50 um", dim::LENGTH) == Approx(0.05).epsilon(1e-12));
    CHECK(parseQuantity("50um", dim::LENGTH) == Approx(0.05).epsilon(1e-12));
    CHECK(parseQuantity("405 nm", dim::LENGTH) == Approx(405e-6).epsilon(1e-12));
    CHECK(parseQuantity("10 mW", dim::POWER) == Approx(10.0).epsilon(1e-12));
    CHECK(parseQuantity("0.2 W", dim::POWER) == Approx(200.0).epsilon(1e-12));
    CHECK(parseQuantity("78 mJ/cm^2", dim::DOSE) == Approx(0.78).epsilon(1e-12));
    CHECK(parseQuantity("78 mJ/cm2", dim::DOSE) == Approx(0.78).epsilon(1e-12));
    CHECK(parseQuantity("84 /cm", dim::INVERSE_LENGTH) == Approx(8.4).epsilon(1e-12));
    CHECK(parseQuantity("84 1/cm", dim::INVERSE_LENGTH) == Approx(8.4).epsilon(1e-12));
    CHECK(parseQuantity("84 cm^-1", dim::INVERSE_LENGTH) == Approx(8.4).epsilon(1e-12));
    CHECK(parseQuantity("1 m/s", dim::SPEED) == Approx(1000.0).epsilon(1e-12));
    CHECK(parseQuantity("5 mW/cm^2", dim::IRRADIANCE) == Approx(0.05).epsilon(1e-12));
    CHECK(parseQuantity("0.03 cm^2/mJ", dim::INVERSE_DOSE) == Approx(3.0).epsilon(1e-12));
    CHECK(parseQuantity("180 deg", dim::ANGLE) == Approx(M_PI).epsilon(1e-12));
    CHECK(parseQuantity("10 ms", dim::TIME) == Approx(0.01).epsilon(1e-12));
    CHECK(parseQuantity("2 \xC2\xB5m", dim::LENGTH) == Approx(0.002).epsilon(1e-12));
    CHECK(parseQuantity("-1.5e-3", dim::LENGTH) == Approx(-1.5e-3).epsilon(1e-12));
}

TEST_CASE("a bare number is taken in base units", "[core][units]") {
    CHECK(parseQuantity("0.05", dim::LENGTH) == 0.05);
    CHECK(quantityFromJson(nlohmann::json(12.5), dim::POWER) == 12.5);
    CHECK(quantityFromJson(nlohmann::json("12.5 mW"), dim::POWER) == Approx(12.5));
}

TEST_CASE("wrong dimensions and malformed units are input errors", "[core][units]") {
    CHECK_THROWS_WITH(parseQuantity("10 mW", dim::LENGTH, "radius", "m.json"),
                      Contains("m.json") && Contains("radius") && Contains("expected length"));
    CHECK_THROWS_AS(parseQuantity("10 furlongs", dim::LENGTH), InputError);
    CHECK_THROWS_WITH(parseQuantity("ten um", dim::LENGTH), Contains("expected a number"));
    CHECK_THROWS_AS(parseQuantity("78 mJ/cm", dim::DOSE), InputError);
    CHECK_THROWS_AS(parseQuantity("5 mm^0", dim::LENGTH), InputError);
    CHECK_THROWS_AS(parseQuantity("inf mm", dim::LENGTH), InputError);
    CHECK_THROWS_AS(quantityFromJson(nlohmann::json::array(), dim::LENGTH), InputError);
}

TEST_CASE("dimensions describe themselves", "[core][units]") {
    CHECK(dim::DOSE.baseUnit() == "mJ/mm^2");
    CHECK(dim::INVERSE_LENGTH.baseUnit() == "1/mm");
    CHECK(dim::POWER.describe() == "power");
}
