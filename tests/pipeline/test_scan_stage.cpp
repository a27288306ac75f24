// The scan stage in a run: trajectories saved in plan.json, build_time_s and scan_order in
// report.json, scan.cli with the plan's layer and vector counts, the scan-path picture.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/exporters/cli_exporter.h"
#include "vpsim/pipeline/run_job.h"

using namespace vpsim;

namespace {

nlohmann::json scanJob() {
    return nlohmann::json::parse(R"({
      "cure": {"model": "threshold", "critical_dose": "10 mJ/cm^2"},
      "part": {"test_part": "pillars", "size": "0.3 mm", "count": 4, "spacing": "0.6 mm",
               "height": "0.1 mm"},
      "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um",
                  "layer_thickness": "50 um", "recoat_time": "2 s",
                  "scanner": {"machine_acceleration": "200 m/s^2", "process_speed": "2 m/s",
                              "delays": {"jump": "200 us"}}},
      "kernel": {"source": "given", "We3D": "60 um", "De3D": "40 um"},
      "plan": {"strategy": "aces", "edge": "cure-at-contour", "order": "exact",
               "direction": "min-edge-projection"},
      "simulation": {"voxel": "10 um", "slices_per_layer": 1, "write_vdb": false}})");
}

std::string writeJob(const nlohmann::json& job) {
    auto path = std::filesystem::temp_directory_path() / "vpsim_job_scan.json";
    std::ofstream(path) << job.dump(1);
    return path.string();
}

}  // namespace

TEST_CASE("a run orders, times and exports its scans", "[pipeline][slow]") {
    auto out = std::filesystem::temp_directory_path() / "vpsim_job_scan";
    std::filesystem::remove_all(out);
    pipeline::Job job = pipeline::loadJob(writeJob(scanJob()), pipeline::makeBuiltins());
    CHECK(job.scanOrder == plan::OrderMethod::Exact);
    CHECK(job.machine.scanner.machine.acceleration == Approx(2e5));
    CHECK(job.machine.recoatTime == Approx(2.0));
    pipeline::runJob(job, out.string(), RunContext{nullptr, false, ""});

    nlohmann::json report = loadJsonFile((out / "report.json").string());
    REQUIRE(report.contains("build_time_s"));
    for (const char* key : {"total", "mark", "jump", "delays", "recoat"})
        CHECK(report["build_time_s"][key].is_number());
    CHECK(report["build_time_s"]["recoat"].get<double>() == Approx(2.0 * 2));
    REQUIRE(report.contains("scan_order"));
    for (const auto& layer : report["scan_order"]["layers"]) {
        CHECK(layer["method"] == "exact");
        CHECK(layer["proven_optimal"] == true);
        CHECK(layer["jump_time_s"].get<double>() <=
              layer["nearest_neighbour_jump_time_s"].get<double>() + 1e-12);
    }

    plan::ScanPlan saved = plan::loadScanPlan((out / "plan.json").string());
    exporters::CliFile cli = exporters::readCli((out / "scan.cli").string());
    REQUIRE(cli.layers.size() == saved.layers.size());
    for (size_t k = 0; k < saved.layers.size(); ++k) {
        size_t marks = 0;
        for (const auto& m : saved.layers[k].trajectory) marks += m.laserOn;
        CHECK(marks >= saved.layers[k].vectors.size());
        CHECK(cli.layers[k].vectorCount() == marks);
    }
    CHECK(std::filesystem::exists(out / "scan_path.svg"));
    std::ifstream html(out / "index.html");
    std::string text((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
    CHECK(text.find("Build time") != std::string::npos);
    CHECK(text.find("scan_path.svg") != std::string::npos);

    nlohmann::json bad = scanJob();
    bad["plan"]["order"] = "random";
    CHECK_THROWS_WITH(pipeline::loadJob(writeJob(bad), pipeline::makeBuiltins()),
                      Catch::Contains("plan.order"));
}
