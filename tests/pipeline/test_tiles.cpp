// Tiled = untiled (issue 22 item 2): a small job run in forced small x-y tiles and in one tile
// gives the same report figures (integers exactly, floating figures within 1e-6 relative) and
// the same cured mesh (triangles, welded vertices, edges, volume): the tiles' seams leave no
// trace.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/output_directory.h"
#include "vpsim/geometry/mesh_check.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/pipeline/run_job.h"

using namespace vpsim;

namespace {

nlohmann::json tileJob(const std::string& tile) {
    nlohmann::json job = nlohmann::json::parse(R"({
      "name": "tiles",
      "cure": {"model": "threshold", "critical_dose": "10 mJ/cm^2"},
      "part": {"test_part": "l-shape", "size": "1 mm", "height": "0.3 mm"},
      "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um",
                  "layer_thickness": "50 um"},
      "kernel": {"source": "given", "We3D": "60 um", "De3D": "40 um"},
      "plan": {"strategy": "aces", "edge": "cure-at-contour"},
      "features": [{"name": "foot", "x": "0.25 mm", "y": "0.25 mm", "z_min": "0 mm",
                    "z_max": "0.3 mm", "kind": "solid", "objective": "0.3 mm"}],
      "simulation": {"voxel": "10 um", "slices_per_layer": 2, "write_vdb": true}})");
    job["simulation"]["tile"] = tile;
    return job;
}

report::JobResult runSpec(const std::string& name, const nlohmann::json& spec,
                          const pipeline::RunOptions& options = {}) {
    const auto dir = std::filesystem::temp_directory_path() / ("vpsim_tiles_" + name);
    const std::string file = dir.string() + ".json";
    std::ofstream(file) << spec.dump(1);
    const pipeline::Job job = pipeline::loadJob(file, pipeline::makeBuiltins());
    return pipeline::runJob(job, dir.string(), RunContext{nullptr, false, ""}, options);
}

report::JobResult runTiles(const std::string& name, const std::string& tile) {
    return runSpec(name, tileJob(tile));
}

nlohmann::json reportOf(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("vpsim_tiles_" + name);
    return loadJsonFile((dir / "report.json").string());
}

/// Keys that are not figures: timings, the job as given (it names the tile), the file list.
bool skipped(const std::string& key) {
    return key.find("seconds") != std::string::npos || key == "inputs" || key == "files" ||
           key == "job_file" || key == "out_dir";
}

/// Every number of `a` against the same place in `b`; `path` names it in failures.
void compareFigures(const nlohmann::json& a, const nlohmann::json& b, const std::string& path,
                    int& compared) {
    INFO(path);
    REQUIRE(a.type() == b.type());
    if (a.is_object()) {
        REQUIRE(a.size() == b.size());
        for (auto it = a.begin(); it != a.end(); ++it) {
            if (skipped(it.key())) continue;
            REQUIRE(b.contains(it.key()));
            compareFigures(it.value(), b.at(it.key()), path + "." + it.key(), compared);
        }
    } else if (a.is_array()) {
        REQUIRE(a.size() == b.size());
        for (size_t i = 0; i < a.size(); ++i)
            compareFigures(a[i], b[i], path + "[" + std::to_string(i) + "]", compared);
    } else if (a.is_number_float()) {
        const double x = a.get<double>(), y = b.get<double>();
        CHECK(std::abs(x - y) <= 1e-6 * std::max(std::abs(x), std::abs(y)) + 1e-12);
        ++compared;
    } else if (a.is_number()) {
        CHECK(a == b);  // integers: exactly
        ++compared;
    }
}

geometry::MeshReport curedMesh(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("vpsim_tiles_" + name);
    geometry::Mesh mesh = geometry::readStlSoup((dir / "cured.stl").string());
    geometry::mergeDuplicateVertices(mesh);
    geometry::MeshCheckOptions options;
    options.repair = false;
    options.throwOnProblem = false;
    return geometry::checkMesh(mesh, "cured.stl", options);
}

}  // namespace

TEST_CASE("a job in small x-y tiles gives the untiled figures and mesh", "[pipeline][tiles]") {
    const report::JobResult whole = runTiles("whole", "auto");
    const report::JobResult tiled = runTiles("tiled", "0.3 mm");
    int compared = 0;
    compareFigures(reportOf("whole"), reportOf("tiled"), "report", compared);
    CHECK(compared > 100);
    // The figures that tiles could most easily disturb, by name.
    CHECK(tiled.exposure.maxDose == whole.exposure.maxDose);
    CHECK(tiled.exposure.storedVoxels == whole.exposure.storedVoxels);
    CHECK(tiled.validation.slices.iou == whole.validation.slices.iou);
    CHECK(tiled.validation.features.simulated == whole.validation.features.simulated);
    CHECK(tiled.curedVolume == Approx(whole.curedVolume).epsilon(1e-6));
    // Every vertex counted once (a seam's halo vertices are not counted again); the statistics'
    // brute-force check is tests/validate/test_deviation_statistics.cpp.
    CHECK(tiled.validation.deviationStatistics.count() ==
          whole.validation.deviationStatistics.count());
    CHECK(tiled.validation.deviation.p95 == whole.validation.deviation.p95);

    // One mesh: the seams' vertices are the owning tile's, so welding by position gives the
    // same vertices, edges and volume, with no open edge the untiled mesh does not have.
    const geometry::MeshReport m = curedMesh("whole"), t = curedMesh("tiled");
    CHECK(t.trianglesIn == m.trianglesIn);
    CHECK(t.verticesIn - t.duplicateVerticesMerged == m.verticesIn - m.duplicateVerticesMerged);
    CHECK(t.openEdges == m.openEdges);
    CHECK(m.openEdges == 0);
    CHECK(t.nonManifoldEdges == m.nonManifoldEdges);
    CHECK(t.volume == Approx(m.volume).epsilon(1e-6));
}

TEST_CASE("the estimate tiles a job that does not fit in one piece", "[pipeline][tiles]") {
    const auto file = (std::filesystem::temp_directory_path() / "vpsim_tiles_fit.json").string();
    nlohmann::json spec = tileJob("auto");
    // A wide margin: the exposure's grid (which tiles shrink) outweighs the cured surface.
    spec["simulation"]["margin"] = "8 mm";
    spec["simulation"]["write_vdb"] = false;
    spec.erase("features");
    std::ofstream(file) << spec.dump(1);
    const pipeline::Job job = pipeline::loadJob(file, pipeline::makeBuiltins());
    const pipeline::JobEstimate whole = pipeline::estimateJob(job);
    CHECK(whole.tileCount == 1);
    RunContext context{nullptr, false, ""};
    context.memoryLimit = uint64_t(whole.peakBytes() - 0.5 * whole.tileBytes);
    const pipeline::JobEstimate fitted = pipeline::fitEstimate(job, context);
    CHECK(fitted.tileCount > 1);
    CHECK(fitted.tileSide > 0);
    CHECK(fitted.peakBytes() <= double(context.memoryLimit));
    CHECK(fitted.tileBytes < whole.tileBytes);
    CHECK_NOTHROW(pipeline::checkEstimate(fitted, context));
    // It says that the tiled run checkpoints (and the untiled one does not).
    CHECK(fitted.checkpointed);
    CHECK_FALSE(whole.checkpointed);
    CHECK(fitted.table(context).find("a checkpoint after each") != std::string::npos);
    CHECK(fitted.toJson(context).at("tiles").at("checkpointed") == true);
    // What tiles cannot shrink is still refused.
    context.memoryLimit = uint64_t(whole.peakBytes() - whole.tileBytes);
    CHECK_THROWS_AS(pipeline::checkEstimate(pipeline::fitEstimate(job, context), context),
                    ResourceError);
}

// 100 x 100 x 50 mm at 10 um (1e13 voxels): without the figures and the 3D view nothing the run
// holds grows with the cured surface, so tiles fit it in a few GiB; with them too, since the
// picture of the cured surface they draw is clustered as it is made (its size follows the view's
// budget, not the 1e9 triangles of the surface).
TEST_CASE("a large part without figures fits in tiles", "[pipeline][tiles]") {
    const auto file = (std::filesystem::temp_directory_path() / "vpsim_tiles_large.json").string();
    nlohmann::json spec = tileJob("auto");
    spec["part"]["size"] = "100 mm";
    spec["part"]["height"] = "50 mm";
    spec["simulation"].erase("write_vdb");
    spec["simulation"]["outputs"] = nlohmann::json::array();
    std::ofstream(file) << spec.dump(1);
    RunContext context{nullptr, false, ""};
    context.memoryLimit = uint64_t(8) << 30;
    const pipeline::Job job = pipeline::loadJob(file, pipeline::makeBuiltins());
    const pipeline::JobEstimate fitted = pipeline::fitEstimate(job, context);
    CHECK(fitted.tileCount > 1);
    CHECK_NOTHROW(pipeline::checkEstimate(fitted, context));
    for (const pipeline::EstimateItem& item : fitted.items) {  // from the exposure on
        INFO(item.name);
        if (item.first >= pipeline::Stage::Expose) CHECK((item.perTile || item.bytes < 1e8));
    }

    spec["simulation"]["outputs"] = {"figures", "viewer"};
    std::ofstream(file) << spec.dump(1);
    const pipeline::Job withFigures = pipeline::loadJob(file, pipeline::makeBuiltins());
    const pipeline::JobEstimate pictured = pipeline::fitEstimate(withFigures, context);
    CHECK_NOTHROW(pipeline::checkEstimate(pictured, context));
    int pictures = 0;
    for (const pipeline::EstimateItem& item : pictured.items)
        if (item.name.find("clustered picture") != std::string::npos) {
            CHECK(item.bytes < 1e8);
            ++pictures;
        }
    CHECK(pictures == 1);
}

// Checkpoint and --resume (issue 22): a tiled run stopped after tile 2 (as a pre-emption would
// stop it) and resumed gives the uninterrupted run's report figures and cured.stl, byte for
// byte; until then its directory has no manifest. A checkpoint of another job, or of the same
// job whose material file changed, is refused, and so is a malformed one; the resumed run
// exposes the checkpoint's plan.json (a changed one is refused) instead of planning again.
TEST_CASE("a tiled run resumed after an interruption gives the uninterrupted result",
          "[pipeline][tiles]") {
    nlohmann::json spec = tileJob("0.3 mm");
    spec["part"]["test_part"] = "bottom-narrow";  // down-facing walls: over-cure runs to save
    spec["simulation"].erase("write_vdb");
    spec["simulation"]["outputs"] = {"cured.stl"};
    const auto tmp = std::filesystem::temp_directory_path();
    // A file the job reads (not used by the given kernel, but its contents are the job's).
    const std::string material = (tmp / "vpsim_tiles_material.json").string();
    const std::string materialText =
        readFile(std::string(VPSIM_SOURCE_DIR) + "/examples/materials/alumina-seed000.json");
    std::ofstream(material, std::ios::binary | std::ios::trunc) << materialText;
    spec["material"] = material;
    std::filesystem::remove_all(tmp / "vpsim_tiles_resume_whole");  // no earlier run's files
    const report::JobResult whole = runSpec("resume_whole", spec);
    REQUIRE(whole.exposure.grid[0] > 0);
    // Without "figures" in the outputs no picture is drawn: not the run's, the planner's review
    // nor the scan path's.
    for (const auto& entry :
         std::filesystem::recursive_directory_iterator(tmp / "vpsim_tiles_resume_whole")) {
        INFO(entry.path());
        CHECK(entry.path().extension() != ".svg");
        CHECK(entry.path().extension() != ".png");
    }

    pipeline::RunOptions stop;
    stop.stopAfterTiles = 2;
    CHECK_THROWS_AS(runSpec("resumed", spec, stop), InputError);
    const auto dir = tmp / "vpsim_tiles_resumed";
    CHECK(std::filesystem::exists(dir / "checkpoint" / "state.json"));
    CHECK_FALSE(verifyOutputDirectory(dir.string()).ok);

    nlohmann::json other = spec;  // another job: its checkpoint is not this one's
    other["cure"]["critical_dose"] = "11 mJ/cm^2";
    pipeline::RunOptions resume;
    resume.resume = true;
    stop.resume = true;
    CHECK_THROWS_WITH(runSpec("resumed", other, resume), Catch::Contains("another job"));
    // The same job document, but its material file edited (one more line break).
    std::ofstream(material, std::ios::binary | std::ios::app) << "\n";
    CHECK_THROWS_WITH(runSpec("resumed", spec, resume), Catch::Contains("another job"));
    std::ofstream(material, std::ios::binary | std::ios::trunc) << materialText;
    // The plan is the checkpoint's plan.json, not planned again: an edited one is refused.
    const std::string planFile = (dir / "plan.json").string(), planText = readFile(planFile);
    std::ofstream(planFile, std::ios::binary | std::ios::app) << " ";
    CHECK_THROWS_WITH(
        runSpec("resumed", spec, resume),
        Catch::Contains("plan.json") && Catch::Contains("changed since the checkpoint"));
    std::ofstream(planFile, std::ios::binary | std::ios::trunc) << planText;
    // A malformed checkpoint: one error naming the file.
    const std::string state = (dir / "checkpoint" / "state.json").string();
    const std::string stateText = readFile(state);
    std::ofstream(state, std::ios::binary | std::ios::trunc) << stateText.substr(0, 40);
    CHECK_THROWS_WITH(runSpec("resumed", spec, resume),
                      Catch::Contains("malformed checkpoint") && Catch::Contains("state.json"));
    // A consumer's state missing (a checkpoint of an older vpsim): the same.
    nlohmann::json older = nlohmann::json::parse(stateText);
    older["consumers"].erase("features");
    std::ofstream(state, std::ios::binary | std::ios::trunc) << older.dump();
    CHECK_THROWS_WITH(runSpec("resumed", spec, resume), Catch::Contains("malformed checkpoint") &&
                                                            Catch::Contains("state.json") &&
                                                            Catch::Contains("features"));
    std::ofstream(state, std::ios::binary | std::ios::trunc) << stateText;

    stop.stopAfterTiles = 4;  // resumed after tile 2, stopped again after tile 4
    CHECK_THROWS_WITH(runSpec("resumed", spec, stop), Catch::Contains("after tile 4"));
    const report::JobResult resumed = runSpec("resumed", spec, resume);
    CHECK_FALSE(std::filesystem::exists(dir / "checkpoint"));
    CHECK(verifyOutputDirectory(dir.string()).ok);
    int compared = 0;
    compareFigures(reportOf("resume_whole"), reportOf("resumed"), "report", compared);
    CHECK(compared > 50);
    CHECK(resumed.validation.deviation.mean == whole.validation.deviation.mean);
    CHECK(resumed.validation.slices.iou == whole.validation.slices.iou);
    CHECK(whole.validation.slices.downFacingColumns > 100);
    CHECK(resumed.validation.slices.overcureBelowDownFacingMean ==
          whole.validation.slices.overcureBelowDownFacingMean);
    CHECK(resumed.curedVolume == whole.curedVolume);
    CHECK(readFile((dir / "cured.stl").string()) ==
          readFile((tmp / "vpsim_tiles_resume_whole" / "cured.stl").string()));
}

// The same with the figures and the 3D view (their state is the whole part's: the sections, the
// picture of the cured surface, the exposure-error map), checkpointed apart in
// checkpoint/pictures-N.bin: the resumed run draws the uninterrupted run's pictures, byte for
// byte, and a changed pictures file is refused naming it.
TEST_CASE("a tiled run with figures and 3D view resumes to the same pictures",
          "[pipeline][tiles]") {
    nlohmann::json spec = tileJob("0.3 mm");
    spec["simulation"].erase("write_vdb");
    spec["simulation"]["outputs"] = {"cured.stl", "figures", "viewer"};
    const auto tmp = std::filesystem::temp_directory_path();
    for (const char* name : {"pictures_whole", "pictures_resumed"})
        std::filesystem::remove_all(tmp / (std::string("vpsim_tiles_") + name));
    runSpec("pictures_whole", spec);
    pipeline::RunOptions stop;
    stop.stopAfterTiles = 2;
    CHECK_THROWS_WITH(runSpec("pictures_resumed", spec, stop), Catch::Contains("after tile 2"));
    const auto dir = tmp / "vpsim_tiles_pictures_resumed";
    const auto pictures = dir / "checkpoint" / "pictures-2.bin";
    REQUIRE(std::filesystem::exists(pictures));

    pipeline::RunOptions resume;
    resume.resume = true;
    const std::string saved = readFile(pictures.string());
    std::string changed = saved;
    changed[changed.size() / 2] ^= 1;
    std::ofstream(pictures, std::ios::binary | std::ios::trunc) << changed;
    CHECK_THROWS_WITH(runSpec("pictures_resumed", spec, resume),
                      Catch::Contains("pictures-2.bin") && Catch::Contains("changed"));
    std::ofstream(pictures, std::ios::binary | std::ios::trunc) << saved;

    stop.resume = true;
    stop.stopAfterTiles = 3;  // a second checkpoint replaces the first's pictures
    CHECK_THROWS_WITH(runSpec("pictures_resumed", spec, stop), Catch::Contains("after tile 3"));
    CHECK_FALSE(std::filesystem::exists(pictures));
    CHECK(std::filesystem::exists(dir / "checkpoint" / "pictures-3.bin"));
    runSpec("pictures_resumed", spec, resume);
    CHECK_FALSE(std::filesystem::exists(dir / "checkpoint"));
    CHECK(verifyOutputDirectory(dir.string()).ok);
    int compared = 0;
    compareFigures(reportOf("pictures_whole"), reportOf("pictures_resumed"), "report", compared);
    CHECK(compared > 50);
    // Every picture and the 3D view's data, byte for byte.
    int files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
        const std::string extension = entry.path().extension().string();
        if (extension != ".png" && extension != ".svg" && extension != ".js" &&
            entry.path().filename() != "cured.stl")
            continue;
        const auto relative = std::filesystem::relative(entry.path(), dir);
        INFO(relative);
        CHECK(readFile(entry.path().string()) ==
              readFile((tmp / "vpsim_tiles_pictures_whole" / relative).string()));
        ++files;
    }
    CHECK(files > 10);
}
