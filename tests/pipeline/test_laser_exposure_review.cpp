// The exposure-error stage of a laser run: every laser strategy reports layer_exposure_error
// (the same metric, the same Etar) and draws the Fig. 23 curve and the top-layer map.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/io.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/pipeline/run_job.h"
#include "vpsim/pipeline/stages.h"
#include "vpsim/plan/scan_plan.h"

using namespace vpsim;

namespace {

std::string writeLaserJob(const std::string& strategy) {
    auto job = nlohmann::json::parse(R"({
      "cure": {"model": "threshold", "critical_dose": "10 mJ/cm^2"},
      "part": {"test_part": "pillars", "size": "0.3 mm", "count": 1, "height": "0.1 mm"},
      "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um",
                  "layer_thickness": "50 um"},
      "kernel": {"source": "given", "We3D": "50 um", "De3D": "100 um"},
      "plan": {"strategy": "aces", "edge": "cure-at-contour"},
      "simulation": {"voxel": "10 um", "slices_per_layer": 1, "write_vdb": false}})");
    job["plan"]["strategy"] = strategy;
    auto path = std::filesystem::temp_directory_path() / ("vpsim_job_laser_" + strategy + ".json");
    std::ofstream(path) << job.dump(1);
    return path.string();
}

}  // namespace

TEST_CASE("every laser strategy reports the exposure error and its pictures", "[pipeline]") {
    double etar = -1;
    for (const std::string strategy : {"aces", "dfbtp", "inverse"}) {
        INFO(strategy);
        auto out = std::filesystem::temp_directory_path() / ("vpsim_job_laser_" + strategy);
        std::filesystem::remove_all(out);
        pipeline::Job job = pipeline::loadJob(writeLaserJob(strategy), pipeline::makeBuiltins());
        pipeline::runJob(job, out.string(), RunContext{nullptr, false, ""});
        nlohmann::json report = loadJsonFile((out / "report.json").string());
        REQUIRE(report.contains("layer_exposure_error"));
        const nlohmann::json& e = report["layer_exposure_error"];
        REQUIRE(e["layers"].size() == 2);
        double sum = 0;
        for (const auto& layer : e["layers"]) sum += layer["sse_mJ2_per_mm4"].get<double>();
        CHECK(e["sse_mJ2_per_mm4"].get<double>() == Approx(sum).epsilon(1e-9));
        CHECK(e["top_layer"]["sse_mJ2_per_mm4"] == e["layers"][1]["sse_mJ2_per_mm4"]);
        // Etar = Ec exp(lt/De3D) for every strategy: 10 e^0.5 mJ/cm^2.
        CHECK(e["target_dose_mJ_per_cm2"].get<double>() == Approx(10 * std::exp(0.5)));
        if (etar < 0) etar = e["target_dose_mJ_per_cm2"];
        CHECK(e["target_dose_mJ_per_cm2"].get<double>() == etar);
        for (const char* file : {"exposure_error_sorted.svg", "exposure_top_layer.svg"}) {
            CHECK(std::filesystem::file_size(out / file) > 1000);
            CHECK(readFile((out / "index.html").string()).find(file) != std::string::npos);
        }
    }
}

// vpsim run takes the metric from its own slices (the top slice of each layer, dz/2 below the
// top, brought to the surface by exp(dz/(2 De))) on the run's grid. The standalone metric,
// exposing the saved plan again layer by layer on that grid, is the same quantity computed
// another way: the same cells count, the figures agree to float rounding (1e-5 relative).
TEST_CASE("vpsim run's exposure error from its slices equals the plan exposed again",
          "[pipeline]") {
    auto spec = loadJsonFile(writeLaserJob("aces"));
    spec["part"] = {{"test_part", "l-shape"}, {"size", "0.8 mm"}, {"height", "0.15 mm"}};
    spec["simulation"]["slices_per_layer"] = 4;
    spec["simulation"].erase("write_vdb");
    spec["simulation"]["outputs"] = {"cured.stl"};
    const auto file = std::filesystem::temp_directory_path() / "vpsim_job_laser_streamed.json";
    std::ofstream(file) << spec.dump(1);
    const auto out = std::filesystem::temp_directory_path() / "vpsim_job_laser_streamed";
    const pipeline::Job job = pipeline::loadJob(file.string(), pipeline::makeBuiltins());
    const RunContext context{nullptr, false, ""};
    pipeline::runJob(job, out.string(), context);
    const nlohmann::json streamed =
        loadJsonFile((out / "report.json").string()).at("layer_exposure_error");

    const geometry::Mesh part = pipeline::partStage(job);
    const pipeline::BeamResult beam = pipeline::beamStage(job, context);
    std::vector<geometry::PolygonSet> regions;
    for (const auto& layer : pipeline::sliceStage(job, part).layers)
        regions.push_back(layer.region);
    REQUIRE(regions.size() == 3);
    exposure::ExposureEngine engine(pipeline::exposureGrid(job, part.bounds(), beam), beam.beam,
                                    job.machine.layerThickness);
    const nlohmann::json standalone =
        optimise::planExposureError(engine, plan::loadScanPlan((out / "plan.json").string()),
                                    regions, streamed["target_dose_mJ_per_cm2"].get<double>() / 100,
                                    streamed["band_um"].get<double>() / 1e3);
    REQUIRE(streamed["layers"].size() == 3);
    for (size_t k = 0; k < 3; ++k)
        for (const char* key : {"sse_mJ2_per_mm4", "rms_over_Etar", "max_over_Etar"}) {
            INFO("layer " << k << " " << key);
            CHECK(streamed["layers"][k][key].get<double>() ==
                  Approx(standalone["layers"][k][key].get<double>()).epsilon(1e-5));
        }
    CHECK(streamed["sse_mJ2_per_mm4"].get<double>() ==
          Approx(standalone["sse_mJ2_per_mm4"].get<double>()).epsilon(1e-5));
    CHECK(streamed["layers"][0]["sse_mJ2_per_mm4"].get<double>() > 0);
}
