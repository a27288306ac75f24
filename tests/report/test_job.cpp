#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/report/run_job.h"

using namespace vpsim;
using Catch::Matchers::Contains;

namespace {

std::string writeJob(const std::string& name, const nlohmann::json& job) {
    auto path = std::filesystem::temp_directory_path() / ("vpsim_job_" + name + ".json");
    std::ofstream(path) << job.dump(1);
    return path.string();
}

nlohmann::json givenKernelJob() {
    return nlohmann::json::parse(R"({
      "cure": {"model": "threshold", "critical_dose": "10 mJ/cm^2"},
      "part": {"test_part": "tapered", "size": "1 mm", "top_size": "0.6 mm", "height": "0.3 mm"},
      "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um", "layer_thickness": "50 um"},
      "kernel": {"source": "given", "We3D": "60 um", "De3D": "40 um"},
      "plan": {"strategy": "aces", "edge": "cure-at-contour"},
      "simulation": {"voxel": "10 um", "slices_per_layer": 2, "write_vdb": false}})");
}

}  // namespace

TEST_CASE("bad jobs give one clear error naming the key", "[report]") {
    auto job = givenKernelJob();
    job["plan"]["stratgy"] = "aces";
    CHECK_THROWS_WITH(report::loadJob(writeJob("typo", job)),
                      Contains("plan.stratgy") && Contains("unknown key"));
    job = givenKernelJob();
    job["machine"]["laser_power"] = "10 mm";
    CHECK_THROWS_WITH(report::loadJob(writeJob("unit", job)),
                      Contains("machine.laser_power") && Contains("power"));
    job = givenKernelJob();
    job["part"] = {{"stl", "no/such/part.stl"}};
    CHECK_THROWS_WITH(report::loadJob(writeJob("stl", job)), Contains("file not found"));
    job = givenKernelJob();
    job["kernel"] = {{"source", "monte-carlo"}};
    CHECK_THROWS_WITH(report::loadJob(writeJob("mc", job)), Contains("material"));
    job = givenKernelJob();
    job["part"]["test_part"] = "teapot";
    CHECK_THROWS_WITH(report::loadJob(writeJob("part", job)), Contains("teapot"));
}

// A whole run on a small frustum with a given kernel: the ACES plan designed to cure at the
// contour should reproduce the part closely. Bounds: IoU > 0.8 (a 1 mm part loses ~0.1 to the
// staircase of 50 um layers on its sloped sides and to the beam's edge blur) and a mean surface
// deviation within one beam radius; no down-facing surfaces, so no over-cure.
TEST_CASE("a small job runs end to end and reproduces its part", "[report][slow]") {
    auto out = std::filesystem::temp_directory_path() / "vpsim_job_run";
    std::filesystem::remove_all(out);
    auto report =
        report::runJob(report::loadJob(writeJob("run", givenKernelJob())), out.string(), nullptr);
    CHECK(report["iou"].get<double>() > 0.8);
    CHECK(std::abs(report["surface_deviation_mm"]["mean"].get<double>()) < 0.05);
    CHECK(report["overcure_below_downfacing_mm"].get<double>() == 0.0);
    for (const char* file : {"report.json", "index.html", "cured.stl", "part.stl", "plan.json",
                             "exposure_xz.png", "exposure_xy.png", "deviation_histogram.svg"})
        CHECK(std::filesystem::exists(out / file));
    CHECK(report["stage_seconds"].contains("expose"));
}

// The Monte Carlo kernel path end to end, exposing with the tabulated kernel: a small photon
// budget keeps it fast; the check is that the table drives the exposure and the part still cures
// close to the model (IoU > 0.7: the 20,000-photon table is noisy), and that the kernel is cached.
TEST_CASE("a Monte Carlo job can expose with the tabulated kernel", "[report][slow]") {
    auto cache = std::filesystem::temp_directory_path() / "vpsim_kernel_cache_test";
    std::filesystem::remove_all(cache);
    setenv("VPSIM_CACHE_DIR", cache.c_str(), 1);
    auto job = givenKernelJob();
    job["material"] = std::string(VPSIM_SOURCE_DIR) + "/examples/materials/alumina-seed000.json";
    job["kernel"] = {
        {"source", "monte-carlo"}, {"photons", 20000}, {"seed", 2}, {"use", "tabulated"}};
    auto out = std::filesystem::temp_directory_path() / "vpsim_job_tabulated";
    auto first = report::runJob(report::loadJob(writeJob("tabulated", job)), out.string(), nullptr);
    CHECK(first["kernel"]["exposure_uses"] == "table");
    CHECK(first["kernel"]["from_cache"] == false);
    CHECK(first["iou"].get<double>() > 0.7);
    auto second =
        report::runJob(report::loadJob(writeJob("tabulated", job)), out.string(), nullptr);
    CHECK(second["kernel"]["from_cache"] == true);
    CHECK(second["iou"].get<double>() == first["iou"].get<double>());
    unsetenv("VPSIM_CACHE_DIR");
}
