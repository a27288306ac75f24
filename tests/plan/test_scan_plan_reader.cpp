// The scan-plan reader: wrong element types, huge masks and unit mistakes are InputErrors naming
// the file and key, never json exceptions.
#include <catch2/catch.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/plan/scan_plan.h"

using namespace vpsim;
using namespace vpsim::plan;
using Catch::Matchers::Contains;

namespace {

std::string messageOf(const std::string& layers, const std::string& machine = "") {
    const std::string text =
        R"({"machine": {"layer_thickness": 0.05, "laser_power": 10, "beam_radius": 0.05,
                        "pixel_pitch": 0.0625)" +
        machine + R"(}, "layers": [)" + layers + "]}";
    try {
        scanPlanFromJson(parseJsonText(text, "p.json"), "p.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

std::string layer(const std::string& points, const std::string& vectors = "[]",
                  const std::string& masks = "[]") {
    return R"({"z": 0.05, "points_x_y_energy": )" + points +
           R"(, "vectors_x0_y0_x1_y1_power_speed": )" + vectors + R"(, "masks": )" + masks + "}";
}

}  // namespace

TEST_CASE("scan-plan elements of the wrong type name the element", "[plan][reader]") {
    CHECK_THAT(messageOf(layer(R"([[0, 0, 1], ["x", 0, 1]])")),
               Contains("p.json: key 'layers[0].points_x_y_energy[1]'"));
    CHECK_THAT(messageOf(layer(R"({"a": 1})")), Contains("expected an array"));
    CHECK_THAT(messageOf(layer("[]", R"([[0, 0, 1, 1, 10, 0]])")),
               Contains("vectors_x0_y0_x1_y1_power_speed[0]") && Contains("speed > 0"));
    CHECK_THAT(messageOf(layer("[]", R"([[0, 0, 1, 1, 10, null]])")), Contains("[0]"));
    CHECK_THAT(messageOf(layer("[[0, 0, 1]]")), Contains("no InputError"));
}

TEST_CASE("scan-plan masks and machine lengths are range-checked", "[plan][reader]") {
    const std::string hugeMask = R"([{"width": 100000000000, "height": 1, "origin_x": 0,
        "origin_y": 0, "pixel_pitch": 0.05, "dose_mJ_per_mm2": [1]}])";
    CHECK_THAT(messageOf(layer("[]", "[]", hugeMask)),
               Contains("masks[0].width") && Contains("mask size must be in"));
    CHECK_THAT(messageOf(layer("[]"), R"(, "extra": 1)"), Contains("unknown key"));
    const std::string text = R"({"machine": {"layer_thickness": 1e9, "laser_power": 10,
        "beam_radius": 0.05, "pixel_pitch": 0.0625}, "layers": []})";
    CHECK_THROWS_WITH(scanPlanFromJson(parseJsonText(text, "p.json"), "p.json"),
                      Contains("machine.layer_thickness") && Contains("at most 10 mm"));
}
