// An optimised-mask run's report: the uniform plan simulated beside it for the features table,
// the DLP figures written and linked from index.html, the figure data kept out of report.json,
// and with xy_coupling both XY contour errors from the run's own validation, the joint one lower.
// Its long planner stages report their progress to the observer.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/core/progress.h"
#include "vpsim/pipeline/run_job.h"
#include "vpsim/report/dlp_figures.h"

using namespace vpsim;

namespace {

/// The last (done, total) the progress observer saw for each label while alive.
class ProgressRecorder {
public:
    ProgressRecorder() {
        Progress::setObserver([this](const std::string& label, uint64_t done, uint64_t total) {
            std::lock_guard<std::mutex> lock(mMutex);
            mLast[label] = {done, total};
        });
    }
    ~ProgressRecorder() { Progress::setObserver(nullptr); }
    std::map<std::string, std::pair<uint64_t, uint64_t>> last() {
        std::lock_guard<std::mutex> lock(mMutex);
        return mLast;
    }

private:
    std::mutex mMutex;
    std::map<std::string, std::pair<uint64_t, uint64_t>> mLast;
};

}  // namespace

TEST_CASE("optimised-mask run: uniform comparison, DLP figures, xy comparison", "[pipeline]") {
    // A small frustum wider at the top (down-facing walls), seed 001's resin and projector.
    const nlohmann::json job = nlohmann::json::parse(R"({
      "cure": {"model": "fpp", "K": "0.0052808 cm^2/mJ", "gel_point": 0.276,
               "penetration_depth": "0.36594 mm"},
      "part": {"test_part": "bottom-narrow", "size": "1.5 mm", "top_size": "0.75 mm",
               "height": "0.6 mm"},
      "machine": {"process": "dlp", "pixel_pitch": "62.5 um", "blur_radius": "40 um",
                  "layer_thickness": "50 um",
                  "grey_levels": [[150, "12.2 mW/cm^2"], [200, "17 mW/cm^2"],
                                  [255, "27 mW/cm^2"]], "exposure_time": "5 s"},
      "plan": {"strategy": "optimised-mask", "xy_coupling": true, "uniform_dose": "78 mJ/cm^2"},
      "simulation": {"voxel": "31.25 um", "slices_per_layer": 5, "write_vdb": false},
      "features": [{"name": "wall", "kind": "solid", "x": "0.6 mm", "y": 0, "z_min": 0,
                    "z_max": "1 mm", "objective": "0.24 mm"}]})");
    const auto dir = std::filesystem::temp_directory_path() / "vpsim_test_dlp_report";
    const auto jobPath = std::filesystem::temp_directory_path() / "vpsim_test_dlp_report.json";
    std::ofstream(jobPath) << job.dump(1);
    pipeline::Job loaded = pipeline::loadJob(jobPath.string(), pipeline::makeBuiltins());
    ProgressRecorder progress;
    report::JobResult r = pipeline::runJob(loaded, dir.string(), RunContext{});
    const nlohmann::json& p = r.plan.planner;
    {
        // The planner's two long stages finished their declared work: every distinct column
        // solved, every FISTA iteration of the joint optimum; the report stage its figures.
        const auto seen = progress.last();
        std::string labels;
        for (const auto& entry : seen) labels += entry.first + "; ";
        INFO("progress labels seen: " << labels);
        using Counts = std::pair<uint64_t, uint64_t>;
        const uint64_t columns = p["distinct_columns"].get<uint64_t>();
        const uint64_t iterations = p["xy_coupling"]["iterations"].get<uint64_t>();
        const std::string columnLabel = "DLP masks: exact optimum of each distinct column";
        const std::string xyLabel =
            "DLP masks: xy coupling (warm starts, step size, FISTA iterations)";
        const std::string reportLabel =
            "report: section, deviation, 3D view and layer error figures";
        REQUIRE(seen.count(columnLabel));
        CHECK(seen.at(columnLabel) == Counts{columns, columns});
        REQUIRE(seen.count(xyLabel));
        CHECK(iterations > 0);
        CHECK(seen.at(xyLabel) == Counts{iterations, iterations});
        REQUIRE(seen.count(reportLabel));
        CHECK(seen.at(reportLabel) == Counts{4, 4});
    }
    REQUIRE_FALSE(p.contains("figures"));
    REQUIRE(p["uniform_comparison"]["dose_mJ_per_cm2"].get<double>() == Approx(78.0));
    REQUIRE(p["uniform_comparison"]["features"][0]["name"] == "wall");
    // Uniform 78 mJ/cm^2 over-cures the down-facing walls' print-through: thicker than planned.
    REQUIRE(p["uniform_comparison"]["features"][0]["simulated_mm"].get<double>() >
            r.validation.features.simulated[0]);
    for (const char* file : report::DLP_FIGURE_FILES) {
        INFO(file);
        REQUIRE(std::filesystem::exists(dir / file));
    }
    std::stringstream html;
    html << std::ifstream(dir / "index.html").rdbuf();
    REQUIRE(html.str().find("dlp_mask.svg") != std::string::npos);
    REQUIRE(html.str().find("XY contour error, this run") != std::string::npos);
    const nlohmann::json& xy = p["xy_coupling"];
    INFO("XY contour error columns " << xy["validation_xy_contour_error_columns_mm"] << " joint "
                                     << xy["validation_xy_contour_error_xy_mm"]);
    REQUIRE(xy["validation_xy_contour_error_xy_mm"].get<double>() ==
            Approx(r.validation.slices.xyContourErrorMean));
    REQUIRE(xy["validation_xy_contour_error_xy_mm"].get<double>() <
            xy["validation_xy_contour_error_columns_mm"].get<double>());
    REQUIRE(xy["objective_xy"].get<double>() <= xy["objective_columns"].get<double>());
    std::filesystem::remove_all(dir);
    std::filesystem::remove(jobPath);
}
