// Material files: the shipped examples load, and every kind of bad file gives one InputError
// that names the file and the offending key.

#include <catch2/catch.hpp>

#include <unistd.h>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>

#include "vpsim/core/error.h"
#include "vpsim/optics/material_file.h"

using namespace vpsim::optics;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;

namespace {

const std::string EXAMPLES = std::string(VPSIM_SOURCE_DIR) + "/examples/materials/";

/// Writes `text` to a fresh file in the temp directory and returns its path.
std::string writeTemp(const std::string& text) {
    static std::atomic<int> counter{0};
    auto path = std::filesystem::temp_directory_path() /
                ("vpsim_material_test_" + std::to_string(::getpid()) + "_" +
                 std::to_string(counter++) + ".json");
    std::ofstream(path) << text;
    return path.string();
}

const char* SLURRY_HEAD =
    R"({"wavelength": "405 nm", "resin": {"refractive_index": 1.45, "penetration_depth": "119 um"},)";

/// The InputError of loading `json`, which must name the file and contain `key` and `reason`.
void expectError(const std::string& json, const std::string& key, const std::string& reason) {
    const std::string path = writeTemp(json);
    INFO(json);
    try {
        loadMediumOptics(path);
        FAIL("no error for a bad material file");
    } catch (const vpsim::InputError& e) {
        INFO(e.what());
        CHECK(e.file() == path);
        CHECK_THAT(std::string(e.what()), Contains(path));
        CHECK_THAT(std::string(e.what()), Contains(key));
        CHECK_THAT(std::string(e.what()), Contains(reason));
    }
    std::filesystem::remove(path);
}

}  // namespace

TEST_CASE("Shipped material files load", "[material]") {
    MediumOptics slab = loadMediumOptics(EXAMPLES + "vandehulst-slab.json");
    CHECK_THAT(slab.mua, WithinRel(1.0, 1e-12));  // 10 /cm = 1 /mm
    CHECK_THAT(slab.mus, WithinRel(9.0, 1e-12));
    CHECK(slab.g == 0.75);
    CHECK(slab.phase == PhaseModel::HenyeyGreenstein);
    CHECK(slab.refractiveIndex == 1.0);
    CHECK(slab.inverseCdf.empty());

    MaterialDefinition alumina = loadMaterialDefinition(EXAMPLES + "alumina-seed000.json");
    REQUIRE(alumina.isSlurry);
    CHECK_THAT(alumina.slurry.wavelength, WithinRel(405e-6, 1e-12));
    CHECK_THAT(alumina.slurry.radius, WithinRel(2.5e-3, 1e-12));
    CHECK_THAT(alumina.slurry.resinPenetrationDepth, WithinRel(0.119, 1e-12));
    CHECK(alumina.slurry.volumeFraction == 0.5);
    MediumOptics m = loadMediumOptics(EXAMPLES + "alumina-seed000.json");
    CHECK(m.phase == PhaseModel::Tabulated);
    CHECK(m.inverseCdf.size() == static_cast<size_t>(DEFAULT_PHASE_TABLE_SIZE));
    CHECK_THAT(m.mua, WithinRel(1.0 / 0.119, 1e-12));
    CHECK_THAT(m.wavelength, WithinRel(405e-6, 1e-12));
    // Overrides reach the file's keys.
    MediumOptics thin =
        loadMediumOptics(EXAMPLES + "alumina-seed000.json", {"particles.volume_fraction=0.25"});
    CHECK_THAT(thin.mus, WithinRel(0.5 * m.mus, 1e-12));
}

TEST_CASE("Slurry options: complex particle index, log-normal sizes, table size, resin fraction",
          "[material]") {
    const std::string path = writeTemp(std::string(SLURRY_HEAD) + R"(
        "particles": {"refractive_index": "1.75-0.001i", "radius": 0.0025, "volume_fraction": 0.4,
                      "size_distribution": {"type": "lognormal", "sigma_g": 1.2, "points": 32}},
        "phase_table_size": 512})");
    MaterialDefinition d = loadMaterialDefinition(path);
    CHECK(d.slurry.particleIndex == Complex(1.75, -0.001));
    CHECK(d.slurry.size.kind == SizeDistribution::Kind::LogNormal);
    CHECK(d.slurry.size.points == 32);
    MediumOptics m = loadMediumOptics(path);
    CHECK(m.inverseCdf.size() == 512u);
    CHECK(m.mua > 1.0 / 0.119);  // the absorbing particles add to the resin absorption
    std::filesystem::remove(path);
}

TEST_CASE("Bad material files give one InputError naming the file and key", "[material]") {
    const std::string particles =
        R"("particles": {"refractive_index": 1.75, "radius": "2.5 um", "volume_fraction": 0.5})";
    // Unknown keys (typos) anywhere.
    expectError(std::string(SLURRY_HEAD) + particles + R"(, "phase_tabel_size": 10})",
                "phase_tabel_size", "unknown key");
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": 1.75, "raduis": "2.5 um", "volume_fraction": 0.5}})",
        "particles.radius", "missing");
    expectError(R"({"optics": {"mua": "10 /cm", "mus": "90 /cm", "g": 0.75, "colour": "red"}})",
                "optics.colour", "unknown key");
    // Wrong units.
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": 1.75, "radius": "2.5 mW", "volume_fraction": 0.5}})",
        "particles.radius", "length");
    expectError(R"({"optics": {"mua": "10 mm", "mus": "90 /cm", "g": 0.75}})", "optics.mua", "");
    expectError(
        R"({"wavelength": "405 parsecs", "resin": {"refractive_index": 1.45, "penetration_depth": "119 um"},)" +
            particles + "}",
        "wavelength", "");
    // Impossible values.
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": 1.75, "radius": "-2.5 um", "volume_fraction": 0.5}})",
        "particles.radius", "positive");
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": 1.75, "radius": "2.5 um", "volume_fraction": 0.74}})",
        "particles.volume_fraction", "0.74");
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": 1.75, "radius": "2.5 um", "volume_fraction": 0}})",
        "particles.volume_fraction", "0.74");
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": 0, "radius": "2.5 um", "volume_fraction": 0.5}})",
        "particles.refractive_index", "positive");
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": "1.75+0.1i", "radius": "2.5 um", "volume_fraction": 0.5}})",
        "particles.refractive_index", "negative imaginary");
    expectError(
        R"({"wavelength": "405 nm", "resin": {"refractive_index": -1.45, "penetration_depth": "119 um"},)" +
            particles + "}",
        "resin.refractive_index", "positive");
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": 1.75, "radius": "2.5 um", "volume_fraction": 0.5,
                       "size_distribution": {"type": "lognormal", "sigma_g": 0.9}}})",
        "particles.size_distribution.sigma_g", "[1, 5]");
    expectError(
        std::string(SLURRY_HEAD) +
            R"("particles": {"refractive_index": 1.75, "radius": "5 mm", "volume_fraction": 0.5}})",
        "particles", "size parameter");
    expectError(R"({"optics": {"mua": "10 /cm", "mus": "90 /cm", "g": 1.0}})", "optics.g",
                "(-1, 1)");
    expectError(R"({"optics": {"mua": "-1 /cm", "mus": "90 /cm", "g": 0.5}})", "optics.mua",
                "negative");
    expectError(R"({"optics": {"mua": 1, "mus": 9, "g": 0.5, "phase": "mie"}})", "optics.phase",
                "hg");
    // Both forms, neither form.
    expectError(std::string(SLURRY_HEAD) + particles + R"(, "optics": {"mua": 1, "mus": 9}})",
                "optics", "not both");
    expectError(R"({"name": "nothing"})", "", "not a material file");
    // Malformed JSON names the file and line.
    expectError("{\n  \"optics\": {\"mua\": 1,,\n}", "", "malformed JSON");
}

TEST_CASE("A missing material file is an InputError naming it", "[material]") {
    CHECK_THROWS_AS(loadMediumOptics("/nonexistent/vpsim/material.json"), vpsim::InputError);
}
