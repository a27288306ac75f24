#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

using namespace vpsim;
using Catch::Matchers::Contains;

namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
    auto path = std::filesystem::temp_directory_path() / ("vpsim_test_" + name);
    std::ofstream(path) << text;
    return path.string();
}

}  // namespace

TEST_CASE("config values are read with units and unknown keys are errors", "[core][config]") {
    std::string path =
        writeTemp("job.json", R"({"laser": {"power": "10 mW", "w0": "50 um"}, "layers": 4})");
    ConfigNode config = ConfigNode::load(path);
    ConfigNode laser = config.child("laser");
    CHECK(laser.quantity("power", dim::POWER) == Approx(10.0));
    CHECK(laser.quantity("w0", dim::LENGTH) == Approx(0.05));
    CHECK(config.integer("layers") == 4);
    CHECK(config.number("missing", 3.5) == 3.5);
    CHECK_NOTHROW(config.checkUnknownKeys());

    std::string typo = writeTemp("typo.json", R"({"laser": {"powr": "10 mW"}})");
    ConfigNode bad = ConfigNode::load(typo);
    bad.child("laser").quantity("power", dim::POWER, 1.0);
    CHECK_THROWS_WITH(bad.checkUnknownKeys(),
                      Contains("typo.json") && Contains("laser.powr") && Contains("unknown key"));
}

TEST_CASE("config type, range and choice errors name the key", "[core][config]") {
    ConfigNode config(nlohmann::json::parse(R"({"a": "x", "f": 1.5, "mode": "zig", "w": "3 mW"})"),
                      "c.json");
    CHECK_THROWS_WITH(config.number("a"),
                      Contains("c.json") && Contains("'a'") && Contains("expected a number"));
    CHECK_THROWS_WITH(config.numberInRange("f", 0.0, 1.0), Contains("outside the allowed range"));
    CHECK_THROWS_WITH(config.choice("mode", {"raster", "aces"}), Contains("raster, aces"));
    CHECK_THROWS_WITH(config.quantity("w", dim::LENGTH),
                      Contains("'w'") && Contains("expected length"));
    CHECK_THROWS_WITH(config.quantity("nothere", dim::LENGTH), Contains("missing required key"));
}

TEST_CASE("malformed JSON reports file and line", "[core][config]") {
    std::string path = writeTemp("broken.json", "{\n  \"a\": 1,\n  \"b\": ,\n}\n");
    CHECK_THROWS_WITH(loadJsonFile(path), Contains("broken.json:3") && Contains("malformed JSON"));
    CHECK_THROWS_WITH(loadJsonFile("/nonexistent/x.json"), Contains("/nonexistent/x.json"));
}

TEST_CASE("set overrides create and replace values", "[core][config]") {
    nlohmann::json doc = nlohmann::json::parse(R"({"particles": {"radius": "2.5 um"}})");
    applyOverride(doc, "particles.radius=3 um");
    applyOverride(doc, "particles.volume_fraction=0.4");
    applyOverride(doc, "machine.laser.power=\"20 mW\"");
    CHECK(doc["particles"]["radius"] == "3 um");
    CHECK(doc["particles"]["volume_fraction"] == 0.4);
    CHECK(doc["machine"]["laser"]["power"] == "20 mW");
    CHECK_THROWS_AS(applyOverride(doc, "novalue"), InputError);
    CHECK_THROWS_AS(applyOverride(doc, "particles.radius.x=1"), InputError);
}

TEST_CASE("atomic writes leave no partial file when writing fails", "[core][io]") {
    auto dir = std::filesystem::temp_directory_path() / "vpsim_atomic";
    std::filesystem::create_directories(dir);
    std::string target = (dir / "out.txt").string();
    writeFileAtomic(target, "complete");
    CHECK(readFile(target) == "complete");
    CHECK_THROWS(writeStreamAtomic(target, [](std::ostream& out) {
        out << "partial";
        throw InputError("simulated failure");
    }));
    CHECK(readFile(target) == "complete");
    size_t files = 0;
    for (auto& entry : std::filesystem::directory_iterator(dir)) files += entry.is_regular_file();
    CHECK(files == 1);
}
