#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/plan/scan_plan.h"

using namespace vpsim;
using Catch::Matchers::Contains;

TEST_CASE("scan plans round-trip through JSON", "[plan]") {
    plan::ScanPlan plan;
    plan.machine.layerThickness = 0.025;
    plan.machine.laserPower = 12.5;
    plan::LayerPlan layer;
    layer.z = 0.025;
    layer.points.push_back({0.1, -0.2, 0.003});
    layer.vectors.push_back({0, 0, 1, 0.5, 10, 250});
    plan::MaskImage mask;
    mask.width = 2;
    mask.height = 1;
    mask.pixelPitch = 0.0625;
    mask.dose = {0.78f, 0.0f};
    layer.masks.push_back(mask);
    plan.layers.push_back(layer);
    auto path = (std::filesystem::temp_directory_path() / "vpsim_plan.json").string();
    plan::saveScanPlan(plan, path);
    plan::ScanPlan loaded = plan::loadScanPlan(path);
    REQUIRE(loaded.layers.size() == 1);
    CHECK(loaded.machine.laserPower == 12.5);
    CHECK(loaded.layers[0].vectors[0].speed == 250);
    CHECK(loaded.layers[0].points[0].energy == 0.003);
    CHECK(loaded.layers[0].masks[0].dose[0] == 0.78f);
    CHECK(loaded.totalEnergy() == Approx(plan.totalEnergy()).epsilon(1e-12));
    // energy = point + vector (P * length / v) + mask (dose * pixel area)
    CHECK(plan.totalEnergy() ==
          Approx(0.003 + 10 * std::hypot(1.0, 0.5) / 250 + 0.78 * 0.0625 * 0.0625).epsilon(1e-6));
}

TEST_CASE("plan.json is written layer by layer, one line each, as the whole tree", "[plan]") {
    // saveScanPlan streams one layer's JSON at a time; parsed, the file must be toJson(plan),
    // each layer on a line of its own: no plan, one layer, and several with a trajectory.
    plan::ScanPlan plan;
    plan.machine.layerThickness = 0.05;
    plan.machine.laserPower = 10;
    auto path = (std::filesystem::temp_directory_path() / "vpsim_plan_stream.json").string();
    auto fileText = [&] {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    plan::saveScanPlan(plan, path);
    CHECK(nlohmann::json::parse(fileText()) == plan::toJson(plan));
    for (int k = 0; k < 3; ++k) {
        plan::LayerPlan layer;
        layer.z = 0.05 * (k + 1);
        layer.vectors.push_back({0, 0.1 * k, 1, 0.1 * k, 10, 250});
        if (k == 1) layer.points.push_back({0.5, 0.5, 0.002});
        if (k == 2) layer.trajectory.push_back({true, 0, 0.2, 1, 0.2, 10, 250, 0, 0});
        plan.layers.push_back(layer);
    }
    plan::saveScanPlan(plan, path);
    const std::string text = fileText();
    CHECK(nlohmann::json::parse(text) == plan::toJson(plan));
    CHECK(std::count(text.begin(), text.end(), '\n') == 3 + 4);  // 3 layers, 4 other lines
    CHECK(plan::loadScanPlan(path).layers.size() == 3);
}

TEST_CASE("malformed scan plans are refused with the key", "[plan]") {
    auto path = (std::filesystem::temp_directory_path() / "vpsim_bad_plan.json").string();
    auto write = [&](const std::string& text) { std::ofstream(path) << text; };
    write(
        R"({"machine": {"layer_thickness": 0.05, "laser_power": 10, "beam_radius": 0.05, "pixel_pitch": 0.06},
              "layers": [{"z": 0.05, "points_x_y_energy": [], "vectors_x0_y0_x1_y1_power_speed": [[0, 0, 1, 0, 10, 0]],
                          "masks": []}]})");
    CHECK_THROWS_WITH(plan::loadScanPlan(path),
                      Contains("vectors_x0_y0_x1_y1_power_speed") && Contains("speed > 0"));
    write(
        R"({"machine": {"layer_thickness": -1, "laser_power": 10, "beam_radius": 0.05, "pixel_pitch": 0.06}, "layers": []})");
    CHECK_THROWS_WITH(plan::loadScanPlan(path), Contains("machine.layer_thickness"));
}
