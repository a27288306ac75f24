// Loading cure laws from JSON sections through the registry: units, alternatives and clear errors
// for bad input.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/fpp_law.h"
#include "vpsim/cure/threshold_law.h"

using namespace vpsim;
using namespace vpsim::cure;
using nlohmann::json;

namespace {

const CureLawRegistry& laws() {
    static const CureLawRegistry registry = [] {
        CureLawRegistry r("cure law");
        registerThresholdLaw(r);
        registerFppLaw(r);
        return r;
    }();
    return registry;
}

const FppLaw& asFpp(const std::unique_ptr<CureLaw>& law) {
    const auto* fpp = dynamic_cast<const FppLaw*>(law.get());
    REQUIRE(fpp != nullptr);
    return *fpp;
}

}  // namespace

TEST_CASE("Cure sections load with units and alternative parameterisations", "[cure]") {
    // 0.00528 cm^2/mJ = 0.528 mm^2/mJ; unit conversion is exact up to rounding (1e-12 rel).
    auto a = cureLawFromJson(laws(), json{{"model", "fpp"},
                                          {"K", "0.00528 cm^2/mJ"},
                                          {"gel_point", 0.276},
                                          {"penetration_depth", "366 um"}});
    REQUIRE(a->name() == "fpp");
    REQUIRE(asFpp(a).rateConstant() == Approx(0.528).epsilon(1e-12));
    REQUIRE(a->penetrationDepth() == Approx(0.366).epsilon(1e-12));

    // Same resin given by its critical dose and attenuation instead of K and Dp.
    auto b = cureLawFromJson(
        laws(), json{{"model", "fpp"},
                     {"critical_dose", std::to_string(100.0 * a->criticalDose()) + " mJ/cm^2"},
                     {"gel_point", 0.276},
                     {"attenuation", std::to_string(10.0 / 0.366) + " /cm"}});
    REQUIRE(asFpp(b).rateConstant() == Approx(0.528).epsilon(1e-6));  // to_string keeps 6 decimals
    REQUIRE(b->penetrationDepth() == Approx(0.366).epsilon(1e-6));

    auto t = cureLawFromJson(laws(), json{{"model", "threshold"}, {"critical_dose", "61 mJ/cm^2"}});
    REQUIRE(t->name() == "threshold");
    REQUIRE(t->criticalDose() == Approx(0.61).epsilon(1e-12));
    REQUIRE_FALSE(t->hasPenetrationDepth());

    // toJson writes base units that load back to the same model.
    for (const CureLaw* m : {a.get(), t.get()}) {
        auto back = cureLawFromJson(laws(), m->toJson());
        REQUIRE(back->name() == m->name());
        REQUIRE(back->criticalDose() == Approx(m->criticalDose()).epsilon(1e-15));
        REQUIRE(back->penetrationDepth() == m->penetrationDepth());
    }
}

TEST_CASE("A cure section inside a material file marks its keys read for the parent", "[cure]") {
    ConfigNode root(
        json{{"wavelength", "405 nm"},
             {"cure",
              {{"model", "threshold"}, {"critical_dose", 0.61}, {"penetration_depth", 0.366}}}},
        "resin.json");
    root.quantity("wavelength", dim::LENGTH);
    auto model = cureLawFromConfig(laws(), root, "cure");
    REQUIRE(model->criticalDose() == 0.61);
    REQUIRE_NOTHROW(root.checkUnknownKeys());
}

namespace {
/// The InputError message for a bad section read as key "cure" of file "resin.json".
std::string errorFor(const json& section) {
    try {
        cureLawFromJson(laws(), section, "resin.json", "cure");
    } catch (const InputError& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace

TEST_CASE("Bad cure sections give one clear error naming the file and key", "[cure]") {
    using Catch::Contains;
    auto fpp = [](json extra) {
        json section{{"model", "fpp"}, {"K", "0.5 mm^2/mJ"}, {"gel_point", 0.276}};
        section.update(extra);
        return section;
    };
    CHECK_THAT(errorFor(fpp({{"Kx", 1.0}})),
               Contains("resin.json") && Contains("cure.Kx") && Contains("unknown key"));
    CHECK_THAT(errorFor(json{{"K", 0.5}}), Contains("cure.model"));
    CHECK_THAT(errorFor(json{{"model", "arrhenius"}}),
               Contains("cure.model") && Contains("fpp, threshold"));
    CHECK_THAT(errorFor(fpp({{"K", "10 mJ"}})), Contains("cure.K"));
    CHECK_THAT(errorFor(fpp({{"K", -0.5}})), Contains("cure.K") && Contains("positive"));
    CHECK_THAT(errorFor(fpp({{"gel_point", 1.2}})), Contains("cure.gel_point"));
    CHECK_THAT(errorFor(fpp({{"critical_dose", 0.6}})), Contains("exactly one of K"));
    CHECK_THAT(errorFor(fpp({{"penetration_depth", "0.3 mm"}, {"attenuation", "3 /mm"}})),
               Contains("not both"));
    CHECK_THAT(errorFor(fpp({{"penetration_depth", "-0.3 mm"}})),
               Contains("cure.penetration_depth"));
    CHECK_THAT(errorFor(json{{"model", "threshold"}, {"critical_dose", 0.6}, {"gel_point", 0.3}}),
               Contains("cure.gel_point") && Contains("unknown key"));
    CHECK_THAT(errorFor(json::array({1, 2})), Contains("resin.json") && Contains("JSON object"));
}
