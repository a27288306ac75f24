// Contracts every registered component keeps, checked by looping over the registries (so a new
// planner, cure law or exporter is covered by adding its registration line):
//  - it is created from its key table's defaults (the required keys at their examples);
//  - the keys it documents are exactly the keys its factory reads;
//  - planners: plan() on a tiny job of its process returns one layer per slice with finite,
//    positive energy, and its size estimate lands within a factor of 8 of the plan it returned;
//  - cure laws: the critical dose is finite and positive, cure is monotone, and toJson() reads
//    back to the same law;
//  - exporters: the tiny plan of their process is accepted and written;
//  - examples/README.md carries the key tables as generated (tools/update-key-docs.sh).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "vpsim/core/io.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/pipeline/run_job.h"

using namespace vpsim;

namespace {

std::string writeJob(const std::string& name, const nlohmann::json& job) {
    auto path = std::filesystem::temp_directory_path() / ("vpsim_contract_" + name + ".json");
    std::ofstream(path) << job.dump(1);
    return path.string();
}

/// A tiny job of each process, the planner and its keys set by the caller.
nlohmann::json tinyJob(plan::Process process) {
    if (process == plan::Process::Laser)
        return nlohmann::json::parse(R"({
          "cure": {"model": "threshold", "critical_dose": "10 mJ/cm^2"},
          "part": {"test_part": "l-shape", "size": "0.6 mm", "height": "0.1 mm"},
          "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um",
                      "layer_thickness": "50 um"},
          "kernel": {"source": "given", "We3D": "50 um", "De3D": "100 um"},
          "simulation": {"voxel": "10 um", "slices_per_layer": 1, "write_vdb": false}})");
    return nlohmann::json::parse(R"({
      "cure": {"model": "fpp", "K": "0.0052808 cm^2/mJ", "gel_point": 0.276,
               "penetration_depth": "0.36594 mm"},
      "part": {"test_part": "box", "size": "0.5 mm", "height": "0.15 mm"},
      "machine": {"process": "dlp", "pixel_pitch": "62.5 um", "blur_radius": "40 um",
                  "layer_thickness": "50 um",
                  "grey_levels": [[150, "12.2 mW/cm^2"], [200, "17 mW/cm^2"],
                                  [255, "27 mW/cm^2"]],
                  "exposure_time": "5 s"},
      "simulation": {"voxel": "31.25 um", "slices_per_layer": 1, "write_vdb": false}})");
}

/// The bytes a plan holds, counted as the estimate counts them (vectors, points, trajectory
/// moves, float mask pixels).
double measuredPlanBytes(const plan::ScanPlan& plan) {
    double bytes = 0;
    for (const plan::LayerPlan& layer : plan.layers) {
        bytes += layer.vectors.size() * sizeof(plan::LaserVector) +
                 layer.points.size() * sizeof(plan::LaserPoint) +
                 layer.trajectory.size() * sizeof(plan::ScanMove);
        for (const plan::MaskImage& mask : layer.masks) bytes += mask.dose.size() * sizeof(float);
    }
    return bytes;
}

double contourVertices(const geometry::LayerStack& layers) {
    double count = 0;
    for (const geometry::Layer& layer : layers.layers)
        for (const geometry::Contour& contour : layer.region.contours())
            count += double(contour.size());
    return count;
}

template <class Component>
void checkKeysRead(const Registry<Component>& registry, const std::string& name) {
    const auto& entry = registry.entry(name);
    ConfigNode section(entry.keys.defaultsSection(), "defaults.json");
    KeyReader keys(entry.keys, section, entry.label(registry.kind()));
    std::unique_ptr<Component> component = entry.factory(keys);
    REQUIRE(component);
    const std::vector<std::string> documented = entry.keys.names();
    CHECK(keys.asked() == std::set<std::string>(documented.begin(), documented.end()));
    section.checkUnknownKeys();  // the defaults hold nothing the component does not read
}

/// The tiny job's planner output: plan and layers, through the pipeline's own stages.
struct Planned {
    pipeline::Job job;
    geometry::Bounds bounds;
    geometry::LayerStack layers;
    plan::ScanPlan plan;
};

Planned planTiny(const std::string& name, plan::Process process,
                 const pipeline::Builtins& builtins) {
    nlohmann::json json = tinyJob(process);
    json["plan"] = builtins.planners.entry(name).keys.defaultsSection();
    json["plan"]["strategy"] = name;
    Planned out{pipeline::loadJob(writeJob(name, json), builtins), {}, {}, {}};
    const RunContext context{nullptr, false, ""};
    const geometry::Mesh part = pipeline::partStage(out.job);
    const pipeline::BeamResult beam = pipeline::beamStage(out.job, context);
    out.bounds = part.bounds();
    out.layers = pipeline::sliceStage(out.job, part);
    out.plan = pipeline::planStage(out.job, out.layers, out.bounds, beam, context).plan;
    pipeline::scanStage(out.job, out.layers, out.plan);
    return out;
}

}  // namespace

TEST_CASE("every planner keeps the planner contract", "[pipeline][contracts]") {
    const pipeline::Builtins builtins = pipeline::makeBuiltins();
    for (const std::string& name : builtins.planners.names()) {
        INFO("planner " << name);
        checkKeysRead(builtins.planners, name);
        const auto& entry = builtins.planners.entry(name);
        const plan::Process process =
            entry
                .factory(KeyReader(entry.keys, ConfigNode(entry.keys.defaultsSection(), ""), name))
                ->process();
        Planned p = planTiny(name, process, builtins);
        REQUIRE(p.plan.layers.size() == p.layers.layers.size());
        const double energy = p.plan.totalEnergy();
        CHECK(std::isfinite(energy));
        CHECK(energy > 0);
        const geometry::Bounds& bounds = p.bounds;
        const planners::PlanSizeInputs inputs{bounds,
                                              bounds.size().x * bounds.size().y * bounds.size().z,
                                              int(p.layers.layers.size()),
                                              p.job.machine,
                                              p.job.machine.beamRadius,
                                              p.job.cure->penetrationDepth(),
                                              contourVertices(p.layers)};
        const double estimated = p.job.planner->estimateSize(inputs).planBytes;
        const double measured = measuredPlanBytes(p.plan);
        INFO("estimated " << estimated << " B, measured " << measured << " B");
        CHECK(estimated <= 8 * measured);
        CHECK(measured <= 8 * estimated);
    }
}

TEST_CASE("every cure law keeps the cure-law contract", "[pipeline][contracts]") {
    const pipeline::Builtins builtins = pipeline::makeBuiltins();
    for (const std::string& name : builtins.cureLaws.names()) {
        INFO("cure law " << name);
        checkKeysRead(builtins.cureLaws, name);
        nlohmann::json section = builtins.cureLaws.entry(name).keys.defaultsSection();
        section["model"] = name;
        const auto law = cure::cureLawFromJson(builtins.cureLaws, section);
        const double ec = law->criticalDose();
        REQUIRE(std::isfinite(ec));
        REQUIRE(ec > 0);
        CHECK_FALSE(law->isCured(0.999 * ec));
        CHECK(law->isCured(ec));
        double last = -1;
        for (double dose = 0; dose <= 4 * ec; dose += ec / 8) {  // conversion never falls
            const double conversion = law->conversion(dose);
            CHECK(conversion >= last);
            last = conversion;
        }
        const auto again = cure::cureLawFromJson(builtins.cureLaws, law->toJson());
        CHECK(again->criticalDose() == Approx(ec).epsilon(1e-12));
        CHECK(again->toJson() == law->toJson());
    }
}

TEST_CASE("every exporter keeps the exporter contract", "[pipeline][contracts]") {
    const pipeline::Builtins builtins = pipeline::makeBuiltins();
    const plan::ScanPlan laser = planTiny("aces", plan::Process::Laser, builtins).plan;
    const plan::ScanPlan masks = planTiny("uniform-mask", plan::Process::Dlp, builtins).plan;
    const auto dir = std::filesystem::temp_directory_path() / "vpsim_contract_exports";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    for (const std::string& name : builtins.exporters.names()) {
        INFO("exporter " << name);
        checkKeysRead(builtins.exporters, name);
        const auto& entry = builtins.exporters.entry(name);
        const auto exporter =
            builtins.exporters.create(name, ConfigNode(entry.keys.defaultsSection(), ""));
        std::string why;
        const plan::ScanPlan& plan = exporter->accepts(laser, why) ? laser : masks;
        REQUIRE(exporter->accepts(plan, why));
        const std::string path = (dir / exporter->defaultFileName()).string();
        exporter->write(plan, path);
        CHECK(std::filesystem::exists(path));
    }
}

TEST_CASE("examples/README.md carries the generated key tables", "[pipeline][contracts]") {
    const std::string readme = readFile(std::string(VPSIM_SOURCE_DIR) + "/examples/README.md");
    const std::string begin = "<!-- component keys: generated by tools/update-key-docs.sh -->\n";
    const std::string end = "<!-- end of component keys -->";
    const size_t a = readme.find(begin), b = readme.find(end);
    REQUIRE(a != std::string::npos);
    REQUIRE(b != std::string::npos);
    const std::string written = readme.substr(a + begin.size(), b - a - begin.size());
    CHECK(written == "\n" + pipeline::componentsMarkdown(pipeline::makeBuiltins()));
}

TEST_CASE("an unknown key names the component and the nearest accepted key",
          "[pipeline][contracts]") {
    const pipeline::Builtins builtins = pipeline::makeBuiltins();
    nlohmann::json json = tinyJob(plan::Process::Laser);
    json["plan"] = {{"strategy", "aces"}, {"homogenity", 0.02}};
    CHECK_THROWS_WITH(pipeline::loadJob(writeJob("typo", json), builtins),
                      Catch::Contains("plan.homogenity") && Catch::Contains("planner 'aces'") &&
                          Catch::Contains("did you mean 'homogeneity'?"));
    // A key the job does not use is still suggested: dot_pitch is dfbtp's, absent here.
    json["plan"] = {{"strategy", "dfbtp"}, {"dot_pich", "20 um"}};
    CHECK_THROWS_WITH(pipeline::loadJob(writeJob("typo2", json), builtins),
                      Catch::Contains("did you mean 'dot_pitch'?"));
    json = tinyJob(plan::Process::Laser);
    json["plan"] = {{"strategy", "aces"}};
    json["simulation"]["voxl"] = "10 um";  // sections that are not components suggest too
    CHECK_THROWS_WITH(pipeline::loadJob(writeJob("typo3", json), builtins),
                      Catch::Contains("did you mean 'voxel'?"));
}
