// CLI export round trip: layer and vector counts of the plan, coordinates within the resolution of
// the units (ASCII: 3 decimals of a unit; binary: float32).
#include <catch2/catch.hpp>

#include <filesystem>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/exporters/cli_exporter.h"
#include "vpsim/plan/aces/aces.h"
#include "vpsim/plan/machine/trajectory.h"

using namespace vpsim;
using namespace vpsim::exporters;
using geometry::PolygonSet;

namespace {

plan::ScanPlan twoLayerPlan() {
    plan::ScanPlan plan;
    for (int i = 0; i < 2; ++i) {
        plan::LayerPlan layer;
        layer.z = 0.05 * (i + 1);
        PolygonSet region = PolygonSet::rectangle({0, 0}, {2.1234567, 1})
                                .unite(PolygonSet::rectangle({4, 0}, {5, 1.5}));
        layer.vectors = plan::hatchRegion(region, 0.1, 0.3 * i, 10, 300);
        // A closed border (a polyline in CLI) around the first square.
        const double b[5][2] = {{0, 0}, {2.1234567, 0}, {2.1234567, 1}, {0, 1}, {0, 0}};
        for (int k = 0; k < 4; ++k)
            layer.vectors.push_back({b[k][0], b[k][1], b[k + 1][0], b[k + 1][1], 10, 300});
        plan.layers.push_back(layer);
    }
    return plan;
}

void checkRoundTrip(const plan::ScanPlan& plan, const CliOptions& options, double tolerance) {
    auto path = (std::filesystem::temp_directory_path() /
                 (options.binary ? "vpsim_test_bin.cli" : "vpsim_test_ascii.cli"))
                    .string();
    CliExporter exporter(options);
    std::string reason;
    REQUIRE(exporter.accepts(plan, reason));
    exporter.write(plan, path);
    CliFile file = readCli(path);
    CHECK(file.binary == options.binary);
    CHECK(file.units == Approx(options.units));
    CHECK(file.version == 200);
    CHECK(file.declaredLayers == int(plan.layers.size()));
    REQUIRE(file.layers.size() == plan.layers.size());
    for (size_t i = 0; i < plan.layers.size(); ++i) {
        const plan::LayerPlan& layer = plan.layers[i];
        const CliLayer& cli = file.layers[i];
        CHECK(cli.z == Approx(layer.z).margin(tolerance));
        size_t marks = 0;
        for (const auto& m : layer.trajectory) marks += m.laserOn;
        if (layer.trajectory.empty()) marks = layer.vectors.size();
        CHECK(cli.vectorCount() == marks);
        CHECK(cli.polylines.size() >= 1);
        // Every CLI hatch is one of the plan's vectors (in mm, within the resolution).
        for (const auto& h : cli.hatches)
            for (const auto& l : h.lines) {
                bool found = false;
                for (const auto& v : layer.vectors)
                    found =
                        found ||
                        (std::abs(v.x0 - l[0]) <= tolerance && std::abs(v.y0 - l[1]) <= tolerance &&
                         std::abs(v.x1 - l[2]) <= tolerance && std::abs(v.y1 - l[3]) <= tolerance);
                CHECK(found);
            }
        // The border is closed and counter-clockwise.
        CHECK(cli.polylines[0].direction == 1);
    }
    std::filesystem::remove(path);
}

}  // namespace

TEST_CASE("CLI round trip, ASCII and binary, with and without trajectories", "[exporters]") {
    plan::ScanPlan plan = twoLayerPlan();
    checkRoundTrip(plan, {false, 1e-3}, 0.5e-6 + 1e-12);  // 3 decimals of 1 um
    checkRoundTrip(plan, {true, 1e-3}, 1e-5);             // float32 of ~5000 um
    plan::attachTrajectories(plan, plan::buildTrajectories(plan, {}));
    checkRoundTrip(plan, {false, 1e-3}, 0.5e-6 + 1e-12);
    checkRoundTrip(plan, {true, 1e-2}, 1e-5);
}

TEST_CASE("CLI exporter options, registry and refusals", "[exporters]") {
    ExporterRegistry registry("exporter");
    registerCliExporter(registry);
    ConfigNode options(nlohmann::json{{"format", "binary"}, {"units", "10 um"}}, "job.json");
    auto exporter = registry.create("cli", options);
    options.checkUnknownKeys();
    CHECK(exporter->defaultFileName() == "scan.cli");
    ConfigNode bad(nlohmann::json{{"format", "xml"}}, "job.json");
    CHECK_THROWS_AS(registry.create("cli", bad), InputError);
    plan::ScanPlan dlp;
    dlp.layers.resize(2);
    std::string reason;
    CHECK_FALSE(exporter->accepts(dlp, reason));
    CHECK_THAT(reason, Catch::Contains("CLI"));
    auto path = (std::filesystem::temp_directory_path() / "vpsim_bad.cli").string();
    writeFileAtomic(path,
                    "$$HEADERSTART\n$$ASCII\n$$UNITS/1\n$$HEADEREND\n$$GEOMETRYSTART\n"
                    "$$LAYER/1\n$$HATCHES/1,2,0,0,1,1\n$$GEOMETRYEND\n");
    CHECK_THROWS_WITH(readCli(path), Catch::Contains("HATCHES"));
    std::filesystem::remove(path);
}
