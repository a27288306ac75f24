// SL1 archive and PNG stack: contents read back with libzip and libpng (entries, ini keys, 8-bit
// greyscale PNGs, the grey of every pixel), and the grey-level calibration's quantisation.
#include <catch2/catch.hpp>

#include <png.h>
#include <zip.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/exporters/grey_masks.h"
#include "vpsim/exporters/png_stack_exporter.h"
#include "vpsim/exporters/sl1_exporter.h"

using namespace vpsim;
using namespace vpsim::exporters;

namespace {

plan::GreyLevels seedLevels() {
    // Seed 001 Fig. 6: gel dose (61 mJ/cm^2) reached just above grey 150 at 5 s.
    return plan::GreyLevels({{150, 0.122}, {200, 0.17}, {255, 0.27}}, 5.0);
}

std::string readEntry(zip_t* archive, const std::string& name) {
    zip_stat_t st;
    REQUIRE(zip_stat(archive, name.c_str(), 0, &st) == 0);
    zip_file_t* f = zip_fopen(archive, name.c_str(), 0);
    REQUIRE(f);
    std::string data(st.size, '\0');
    REQUIRE(zip_fread(f, data.data(), st.size) == zip_int64_t(st.size));
    zip_fclose(f);
    return data;
}

struct Decoded {
    int width = 0, height = 0, bitDepth = 0, colourType = -1;
    std::vector<uint8_t> pixels;
};

Decoded decodePng(const std::string& data) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_memory(&image, data.data(), data.size()));
    Decoded d;
    d.width = int(image.width), d.height = int(image.height);
    // IHDR: bytes 24 and 25 of the file are bit depth and colour type.
    d.bitDepth = uint8_t(data[24]), d.colourType = uint8_t(data[25]);
    image.format = PNG_FORMAT_GRAY;
    d.pixels.resize(PNG_IMAGE_SIZE(image));
    REQUIRE(png_image_finish_read(&image, nullptr, d.pixels.data(), 0, nullptr));
    return d;
}

plan::ScanPlan rampPlan(const plan::GreyLevels& levels, int layers) {
    plan::ScanPlan p;
    p.machine.layerThickness = 0.05;
    p.machine.pixelPitch = 0.0625;
    for (int k = 0; k < layers; ++k) {
        plan::LayerPlan layer;
        layer.z = 0.05 * (k + 1);
        plan::MaskImage m;
        m.width = 16, m.height = 4, m.pixelPitch = 0.0625;
        for (int i = 0; i < 64; ++i) m.dose.push_back(float(levels.dose(150 + i + k)));
        m.dose[0] = 0.0f;
        layer.masks.push_back(m);
        p.layers.push_back(layer);
    }
    return p;
}

}  // namespace

TEST_CASE("Grey levels: dose of a grey and quantisation round trip", "[exporters]") {
    plan::GreyLevels g = seedLevels();
    REQUIRE(g.dose(0) == 0.0);
    REQUIRE(g.dose(149) == 0.0);
    REQUIRE(g.dose(150) == Approx(0.61).epsilon(1e-12));  // 0.122 mW/mm^2 x 5 s
    REQUIRE(g.dose(255) == Approx(1.35).epsilon(1e-12));
    REQUIRE(g.irradiance(175) == Approx(0.146).epsilon(1e-12));  // linear between points
    for (int grey = 150; grey <= 255; ++grey) REQUIRE(g.quantise(g.dose(grey)) == grey);
    REQUIRE(g.quantise(0.0) == 0);
    REQUIRE(g.quantise(0.2) == 0);    // nearer to dark than to grey 150's 0.61
    REQUIRE(g.quantise(0.4) == 150);  // nearer to grey 150
    REQUIRE(g.quantise(9.0) == 255);
    // Quantisation error at most half a step: steps are <= 0.0245 mJ/mm^2 here.
    for (double d = 0.62; d < 1.35; d += 0.001)
        REQUIRE(std::abs(g.dose(g.quantise(d)) - d) <= 0.5 * 0.0245 + 1e-12);
    REQUIRE_THROWS_AS(plan::GreyLevels({{150, 0.2}, {140, 0.3}}, 5.0), InputError);
    REQUIRE_THROWS_AS(plan::GreyLevels({{150, 0.2}}, 0.0), InputError);
}

TEST_CASE("Grey levels: parsed from a machine section with units", "[exporters]") {
    ConfigNode root(nlohmann::json::parse(R"({"machine": {"grey_levels": [[150, "12.2 mW/cm^2"],
        [255, 0.27]], "exposure_time": "5 s"}})"),
                    "job.json");
    plan::GreyLevels g = plan::greyLevelsFromConfig(root.child("machine"));
    REQUIRE(g.irradiance(150) == Approx(0.122).epsilon(1e-12));
    REQUIRE(g.exposureTime() == 5.0);
    ConfigNode bad(nlohmann::json::parse(R"({"grey_levels": [[150]], "exposure_time": 5})"),
                   "job.json");
    REQUIRE_THROWS_WITH(plan::greyLevelsFromConfig(bad), Catch::Contains("grey_levels"));
}

TEST_CASE("SL1: archive holds config.ini, prusaslicer.ini and one 8-bit grey PNG per layer",
          "[exporters]") {
    plan::GreyLevels levels = seedLevels();
    plan::ScanPlan p = rampPlan(levels, 3);
    Sl1Settings s;
    s.displayPixelsX = 20, s.displayPixelsY = 6;
    Sl1Exporter exporter(levels, s);
    std::string reason;
    REQUIRE(exporter.accepts(p, reason));
    const std::string path =
        (std::filesystem::temp_directory_path() / "vpsim_test_print.sl1").string();
    exporter.write(p, path);
    int error = 0;
    zip_t* archive = zip_open(path.c_str(), ZIP_RDONLY, &error);
    REQUIRE(archive);
    REQUIRE(zip_get_num_entries(archive, 0) == 5);
    std::string config = readEntry(archive, "config.ini");
    REQUIRE_THAT(config, Catch::Contains("expTime = 5\n"));
    REQUIRE_THAT(config, Catch::Contains("layerHeight = 0.05\n"));
    REQUIRE_THAT(config, Catch::Contains("jobDir = print\n"));
    std::string profile = readEntry(archive, "prusaslicer.ini");
    REQUIRE_THAT(profile, Catch::Contains("display_pixels_x = 20\n"));
    REQUIRE_THAT(profile, Catch::Contains("display_pixels_y = 6\n"));
    REQUIRE_THAT(profile, Catch::Contains("display_width = 1.25\n"));  // 20 x 62.5 um
    REQUIRE_THAT(profile, Catch::Contains("display_height = 0.375\n"));
    for (int k = 0; k < 3; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "print%05d.png", k);
        Decoded d = decodePng(readEntry(archive, name));
        REQUIRE(d.width == 20);
        REQUIRE(d.height == 6);
        REQUIRE(d.bitDepth == 8);
        REQUIRE(d.colourType == 0);  // greyscale
        // The mask sits centred (offset 2, 1); pixel i has grey 150 + i + k, pixel 0 is dark.
        for (int i = 1; i < 64; ++i)
            REQUIRE(d.pixels[size_t(1 + i / 16) * 20 + size_t(2 + i % 16)] == 150 + i + k);
        REQUIRE(d.pixels[1 * 20 + 2] == 0);
        REQUIRE(d.pixels[0] == 0);
    }
    zip_close(archive);
    std::filesystem::remove(path);
}

TEST_CASE("SL1: refuses plans it cannot express and doses above the brightest grey",
          "[exporters]") {
    plan::GreyLevels levels = seedLevels();
    Sl1Exporter exporter(levels, {});
    plan::ScanPlan laser;
    laser.layers.resize(1);
    laser.layers[0].vectors.push_back({});
    std::string reason;
    REQUIRE_FALSE(exporter.accepts(laser, reason));
    plan::ScanPlan hot = rampPlan(levels, 1);
    hot.layers[0].masks[0].dose[5] = 2.0f;  // 200 mJ/cm^2 > 135
    REQUIRE_THROWS_WITH(exporter.write(hot, "/tmp/vpsim_test_hot.sl1"),
                        Catch::Contains("brightest grey"));
    REQUIRE_FALSE(std::filesystem::exists("/tmp/vpsim_test_hot.sl1"));
}

TEST_CASE("PNG stack: one 8-bit grey PNG per layer", "[exporters]") {
    plan::GreyLevels levels = seedLevels();
    plan::ScanPlan p = rampPlan(levels, 2);
    const std::string dir = (std::filesystem::temp_directory_path() / "vpsim_test_masks").string();
    std::filesystem::remove_all(dir);
    PngStackExporter(levels).write(p, dir);
    for (int k = 0; k < 2; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "/layer%05d.png", k);
        std::FILE* f = std::fopen((dir + name).c_str(), "rb");
        REQUIRE(f);
        std::string data(1 << 16, '\0');
        data.resize(std::fread(data.data(), 1, data.size(), f));
        std::fclose(f);
        Decoded d = decodePng(data);
        REQUIRE(d.bitDepth == 8);
        REQUIRE(d.colourType == 0);
        REQUIRE(d.pixels[10] == 160 + k);
    }
    REQUIRE(std::filesystem::exists(dir + "/masks.json"));
    std::filesystem::remove_all(dir);
}
