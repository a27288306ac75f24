// The DLP report figures: each SVG is written from its data, with axes, units and scales, and
// index.html's DLP section shows the uniform and the optimised features side by side.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/svg_text.h"
#include "vpsim/report/dlp_figures.h"

using namespace vpsim;

namespace {

std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST_CASE("DLP figures: features, along Z, mask and histogram with axes and scales", "[report]") {
    const auto dir = std::filesystem::temp_directory_path() / "vpsim_test_dlp_figures";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    // A 3-layer plan of 4 x 2 pixels; grey g has dose g/255 x 1.35 mJ/mm^2.
    plan::ScanPlan plan;
    nlohmann::json greyDose = nlohmann::json::array();
    for (int g = 0; g < 256; ++g) greyDose.push_back(135.0 * g / 255.0);
    for (int k = 0; k < 3; ++k) {
        plan::LayerPlan layer;
        layer.z = 0.05 * (k + 1);
        plan::MaskImage m;
        m.width = 4, m.height = 2, m.pixelPitch = 0.0625, m.originX = -0.125;
        for (int p = 0; p < 8; ++p)
            m.dose.push_back(p % 4 == 0 ? 0.0f : float(1.35 * (150 + p) / 255));
        layer.masks.push_back(m);
        plan.layers.push_back(layer);
    }
    nlohmann::json data = {{"layer", 1},
                           {"grey_dose_mJ_per_cm2", greyDose},
                           {"column",
                            {{"z_mm", {0.05, 0.1, 0.15}},
                             {"solid", {true, false, true}},
                             {"dose_mJ_per_cm2", {80.0, 0.0, 90.0}},
                             {"quantised_dose_mJ_per_cm2", {79.4, 0.0, 90.0}},
                             {"conversion", {0.9, 0.3, 0.95}},
                             {"x_mm", 0.03},
                             {"y_mm", 0.03},
                             {"gel_point", 0.276},
                             {"target_conversion", 0.95}}}};
    std::vector<double> histogram(256, 0.0);
    histogram[151] = 3, histogram[155] = 1000;
    validate::FeatureProbe hole;
    hole.name = "hole", hole.objective = 1.5, hole.measured = {1.35, 1.31};
    const validate::FeatureMeasurements features{{hole}, {1.34}};
    report::writeDlpFigures(dir.string(), {plan, data, features, {0.72}, histogram});
    for (const char* file : report::DLP_FIGURE_FILES) {
        INFO(file);
        REQUIRE(std::filesystem::exists(dir / file));
        REQUIRE(readText(dir / file).find("<svg") != std::string::npos);
        const std::string png = std::filesystem::path(file).replace_extension(".png").string();
        REQUIRE(std::filesystem::exists(dir / png));
    }
    REQUIRE(test::hasText(readText(dir / "dlp_features.svg"), "length (mm)"));
    REQUIRE(test::hasText(readText(dir / "dlp_features.svg"), "uniform plan"));
    REQUIRE(test::hasText(readText(dir / "dlp_dose_along_z.svg"), "dose (mJ/cm"));
    REQUIRE(test::hasText(readText(dir / "dlp_conversion_along_z.svg"), "gel point"));
    const std::string mask = readText(dir / "dlp_mask.svg");
    REQUIRE(test::hasText(mask, "x (mm)"));
    REQUIRE(test::hasText(mask, "Mask of layer 1"));
    REQUIRE(test::hasText(mask, "255 = 135 mJ/cm"));  // the grey/dose scale
    REQUIRE(test::hasText(mask, "dose of the grey level"));
    REQUIRE(test::hasText(readText(dir / "dlp_grey_histogram.svg"), "grey level"));
    // The uniform plan's bar: 0.72 mm drawn beside the objective, this plan and the measured.
    REQUIRE(test::hasText(readText(dir / "dlp_features.svg"), "uniform plan (simulated)"));
    std::filesystem::remove_all(dir);
}
