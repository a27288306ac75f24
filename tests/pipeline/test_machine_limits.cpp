// Every laser planner plans within the machine's limits, and a job whose dose the machine cannot
// deliver is refused before planning (issue 23 item 1).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/pipeline/run_job.h"
#include "vpsim/plan/machine/build_time.h"
#include "vpsim/plan/machine/laser_limits.h"

using namespace vpsim;

namespace {

/// A small two-layer L with a given kernel on seed 002's scanner (process 0.3 m/s), a laser of
/// 10 mW down to 0.2 mW.
pipeline::Job limitsJob(const std::string& strategy, const std::string& powerMin) {
    nlohmann::json job = nlohmann::json::parse(R"({
      "cure": {"model": "threshold", "critical_dose": "10 mJ/cm^2"},
      "part": {"test_part": "l-shape", "size": "0.6 mm", "height": "0.1 mm"},
      "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um",
                  "layer_thickness": "50 um"},
      "kernel": {"source": "given", "We3D": "50 um", "De3D": "100 um"},
      "plan": {"strategy": "aces", "edge": "cure-at-contour"},
      "simulation": {"voxel": "10 um", "slices_per_layer": 1, "write_vdb": false}})");
    job["plan"]["strategy"] = strategy;
    job["machine"]["laser_power_min"] = powerMin;
    auto path = std::filesystem::temp_directory_path() / ("vpsim_limits_" + strategy + ".json");
    std::ofstream(path) << job.dump(1);
    return pipeline::loadJob(path.string(), pipeline::makeBuiltins());
}

}  // namespace

TEST_CASE("aces, dfbtp and inverse plan within the power range and the process speed",
          "[pipeline][slow]") {
    for (const std::string strategy : {"aces", "dfbtp", "inverse"}) {
        INFO(strategy);
        auto out = std::filesystem::temp_directory_path() / ("vpsim_limits_" + strategy);
        std::filesystem::remove_all(out);
        const pipeline::Job job = limitsJob(strategy, "0.2 mW");
        const pipeline::PlanResult planned =
            pipeline::planJob(job, out.string(), RunContext{nullptr, false, ""});
        const nlohmann::json use = plan::laserUseJson(planned.plan, 0.2, 300);
        REQUIRE(use.is_object());
        CHECK(use["marks_above_process_speed"] == 0);
        CHECK(use["marks_below_min_power"] == 0);
        CHECK(use["marks_above_max_power"] == 0);
        CHECK(use["power_mW"][0].get<double>() >= 0.2 * (1 - 1e-9));
        CHECK(use["power_mW"][1].get<double>() <= 10 * (1 + 1e-9));
        const plan::BuildTime time =
            plan::estimateBuildTime(planned.plan, plan::buildTimeOptions(job.machine));
        CHECK(time.sum.marksAboveProcessSpeed == 0);
        // The fit's counts are in the planner's summary (report.json "laser").
        REQUIRE(planned.summary.contains("laser"));
        CHECK(planned.summary["laser"].contains("dropped_negligible"));
        std::filesystem::remove_all(out);
    }
}

TEST_CASE("a dose below what the minimum power gives is refused before planning", "[pipeline]") {
    auto out = std::filesystem::temp_directory_path() / "vpsim_limits_refused";
    std::filesystem::remove_all(out);
    const pipeline::Job job = limitsJob("inverse", "9 mW");
    try {
        pipeline::planJob(job, out.string(), RunContext{nullptr, false, ""});
        FAIL("not refused");
    } catch (const InputError& e) {
        const std::string message = e.what();
        CHECK(message.find('\n') == std::string::npos);
        CHECK(message.find("machine.laser_power_min") != std::string::npos);
        CHECK(message.find("process_speed") != std::string::npos);
    }
    CHECK_FALSE(std::filesystem::exists(out / "plan.json"));  // nothing planned or written
    std::filesystem::remove_all(out);
}
