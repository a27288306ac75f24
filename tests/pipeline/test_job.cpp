#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/pipeline/run_job.h"
#include "vpsim/pipeline/stages.h"
#include "vpsim/planners/inverse_planner.h"
#include "vpsim/planners/laser_plan_options.h"

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
      "machine": {"process": "laser", "laser_power": "10 mW", "beam_radius": "50 um",
                  "layer_thickness": "50 um"},
      "kernel": {"source": "given", "We3D": "60 um", "De3D": "40 um"},
      "plan": {"strategy": "aces", "edge": "cure-at-contour"},
      "simulation": {"voxel": "10 um", "slices_per_layer": 2, "write_vdb": false}})");
}

pipeline::Job load(const std::string& name, const nlohmann::json& job,
                   const pipeline::Builtins& builtins = pipeline::makeBuiltins()) {
    return pipeline::loadJob(writeJob(name, job), builtins);
}

RunContext cpuContext(const std::string& cache = "") {
    return RunContext{nullptr, false, cache};
}

}  // namespace

TEST_CASE("bad jobs give one clear error naming the key", "[pipeline]") {
    auto job = givenKernelJob();
    job["plan"]["stratgy"] = "aces";
    CHECK_THROWS_WITH(load("typo", job), Contains("plan.stratgy") && Contains("unknown key"));
    job = givenKernelJob();
    job["machine"]["laser_power"] = "10 mm";
    CHECK_THROWS_WITH(load("unit", job), Contains("machine.laser_power") && Contains("power"));
    job = givenKernelJob();
    job["part"] = {{"stl", "no/such/part.stl"}};
    CHECK_THROWS_WITH(load("stl", job), Contains("file not found"));
    job = givenKernelJob();
    job["kernel"] = {{"source", "monte-carlo"}};
    CHECK_THROWS_WITH(load("mc", job), Contains("material"));
    job = givenKernelJob();
    job["part"]["test_part"] = "teapot";
    CHECK_THROWS_WITH(load("part", job), Contains("teapot"));
    job = givenKernelJob();
    job["plan"] = {{"strategy", "uniform-mask"}};
    CHECK_THROWS_WITH(load("process", job), Contains("plan.strategy") && Contains("dlp process"));
    job = givenKernelJob();
    job["plan"]["dose"] = "78 mJ/cm^2";  // a uniform-mask key on an ACES job
    CHECK_THROWS_WITH(load("foreign", job), Contains("plan.dose") && Contains("unknown key"));
    // write_vdb beside outputs: accepted when both say the same, refused when they disagree.
    job = givenKernelJob();
    job["simulation"]["outputs"] = {"cured.stl"};
    CHECK_FALSE(load("agree", job).simulation.writeVdb);
    job["simulation"]["write_vdb"] = true;
    CHECK_THROWS_WITH(load("disagree", job),
                      Contains("simulation.write_vdb") && Contains("leaves out exposure.vdb"));
}

namespace {

/// A planner defined here, registered without touching the pipeline: it exposes one spot of
/// `energy` at the centre of every layer, sizes itself and adds its own review to the report.
class SpotPlanner : public planners::Planner {
public:
    explicit SpotPlanner(double energy) : mEnergy(energy) {}
    plan::Process process() const override { return plan::Process::Laser; }
    plan::ScanPlan plan(const planners::PlannerInputs& in) override {
        plan::ScanPlan p = plan::emptyPlan(in.layers, in.machine);
        const geometry::Bounds& b = in.partBounds;
        for (auto& layer : p.layers)
            layer.points.push_back({0.5 * (b.lo.x + b.hi.x), 0.5 * (b.lo.y + b.hi.y), mEnergy});
        return p;
    }
    nlohmann::json summary() const override { return {{"spot", {{"energy_mJ", mEnergy}}}}; }
    planners::PlanSize estimateSize(const planners::PlanSizeInputs& in) const override {
        planners::PlanSize size;
        size.planBytes = 1234.0 * in.layers;  // a recognisable figure for the estimate
        size.detail = "one spot per layer";
        return size;
    }
    planners::PlanReview review(const planners::PlanReviewInputs& in) const override {
        planners::PlanReview review;
        review.report["spot_review"] = {{"layers", in.plan.layers.size()}};
        review.sections.push_back({"Spot", {{{"energy (mJ)"}, {{std::to_string(mEnergy)}}}}, {}});
        return review;
    }

private:
    double mEnergy;
};

}  // namespace

TEST_CASE("a planner registered from a test plans, sizes and reviews a job", "[pipeline]") {
    pipeline::Builtins builtins = pipeline::makeBuiltins();
    builtins.planners.add(
        {"spot",
         "one spot per layer",
         {{quantityKey("energy", dim::ENERGY, "2 uJ", "energy of each spot").positiveOnly()}},
         [](const KeyReader& keys) {
             return std::make_unique<SpotPlanner>(keys.quantity("energy"));
         }});
    auto json = givenKernelJob();
    json["plan"] = {{"strategy", "spot"}, {"energy", 0.002}};
    pipeline::Job job = load("spot", json, builtins);
    auto out = std::filesystem::temp_directory_path() / "vpsim_job_spot";
    pipeline::PlanResult plan = pipeline::planJob(job, out.string(), cpuContext());
    REQUIRE(plan.plan.layers.size() == 6);  // 0.3 mm in 50 um layers
    REQUIRE(plan.plan.totalEnergy() == Approx(6 * 0.002));
    REQUIRE(plan.summary["spot"]["energy_mJ"] == 0.002);
    // Its size in the job's estimate, its keys in the listing, its review in the report.
    const nlohmann::json estimate = pipeline::estimateJob(job, true).toJson(RunContext{});
    bool sized = false;
    for (const auto& item : estimate["memory"])
        sized |= item.value("bytes", 0.0) == 1234.0 * 6 &&
                 item.value("detail", "") == "one spot per layer";
    CHECK(sized);
    const nlohmann::json listed = pipeline::registryJson(builtins.planners);
    bool keys = false;
    for (const auto& p : listed)
        keys |= p["name"] == "spot" && p["keys"][0]["name"] == "energy" &&
                p["keys"][0]["default"] == "2 uJ";
    CHECK(keys);
    json["plan"] = {{"strategy", "spot"}};  // the default energy, 2 uJ
    report::JobResult result =
        pipeline::runJob(load("spot2", json, builtins), out.string(), cpuContext());
    CHECK(result.plan.planner["spot_review"]["layers"] == 6);
    CHECK(result.plan.energy == Approx(6 * 0.002));
    REQUIRE(result.sections.size() == 1);
    CHECK(result.sections[0].title == "Spot");
}

// A whole run on a small frustum with a given kernel: the ACES plan designed to cure at the
// contour should reproduce the part closely. Bounds: IoU > 0.8 (a 1 mm part loses ~0.1 to the
// staircase of 50 um layers on its sloped sides and to the beam's edge blur) and a mean surface
// deviation within one beam radius; no down-facing surfaces, so no over-cure.
TEST_CASE("a small job runs end to end and reproduces its part", "[pipeline][slow]") {
    auto out = std::filesystem::temp_directory_path() / "vpsim_job_run";
    std::filesystem::remove_all(out);
    report::JobResult r =
        pipeline::runJob(load("run", givenKernelJob()), out.string(), cpuContext());
    CHECK(r.validation.slices.iou > 0.8);
    CHECK(std::abs(r.validation.deviation.mean) < 0.05);
    CHECK(r.validation.slices.overcureBelowDownFacingMedian == 0.0);
    for (const char* file : {"report.json", "index.html", "cured.stl", "part.stl", "plan.json",
                             "exposure_xz.png", "exposure_xy.png", "deviation_histogram.svg"})
        CHECK(std::filesystem::exists(out / file));
    CHECK(report::toJson(r)["stage_seconds"].contains("expose"));
}

// Resumable runs: plan, then run from the saved plan (in the same output directory, which the
// run overwrites) gives exactly the one-shot run's figures; a plan that does not fit the job is
// refused with the file named.
TEST_CASE("vpsim plan then run --plan equals a one-shot run", "[pipeline][slow]") {
    pipeline::Job job = load("resume", givenKernelJob());
    auto oneShotDir = std::filesystem::temp_directory_path() / "vpsim_job_oneshot";
    auto resumedDir = std::filesystem::temp_directory_path() / "vpsim_job_resumed";
    report::JobResult oneShot = pipeline::runJob(job, oneShotDir.string(), cpuContext());
    pipeline::planJob(job, resumedDir.string(), cpuContext());
    pipeline::RunOptions options;
    options.planFile = (resumedDir / "plan.json").string();
    report::JobResult resumed = pipeline::runJob(job, resumedDir.string(), cpuContext(), options);
    CHECK(resumed.validation.slices.iou == oneShot.validation.slices.iou);
    CHECK(resumed.validation.deviation.mean == oneShot.validation.deviation.mean);
    CHECK(resumed.validation.deviation.rms == oneShot.validation.deviation.rms);
    CHECK(resumed.plan.energy == oneShot.plan.energy);

    auto other = givenKernelJob();
    other["part"]["height"] = "0.5 mm";  // 10 layers, the plan has 6
    options.planFile = (oneShotDir / "plan.json").string();
    CHECK_THROWS_WITH(
        pipeline::runJob(load("taller", other), resumedDir.string(), cpuContext(), options),
        Contains("plan.json") && Contains("6 layers"));
}

// The Monte Carlo kernel path end to end, exposing with the tabulated kernel: a small photon
// budget keeps it fast; the check is that the table drives the exposure and the part still cures
// close to the model (IoU > 0.7: the 20,000-photon table is noisy), and that the kernel is cached.
TEST_CASE("a Monte Carlo job can expose with the tabulated kernel", "[pipeline][slow]") {
    auto cache = std::filesystem::temp_directory_path() / "vpsim_kernel_cache_test";
    std::filesystem::remove_all(cache);
    auto job = givenKernelJob();
    job["material"] = std::string(VPSIM_SOURCE_DIR) + "/examples/materials/alumina-seed000.json";
    job["kernel"] = {
        {"source", "monte-carlo"}, {"photons", 20000}, {"seed", 2}, {"use", "tabulated"}};
    auto out = std::filesystem::temp_directory_path() / "vpsim_job_tabulated";
    report::JobResult first =
        pipeline::runJob(load("tabulated", job), out.string(), cpuContext(cache.string()));
    REQUIRE(first.kernel);
    CHECK(first.kernel->tabulatedExposure);
    CHECK(first.exposure.model == "tabulated");
    CHECK_FALSE(first.kernel->fromCache);
    CHECK(first.validation.slices.iou > 0.7);
    report::JobResult second =
        pipeline::runJob(load("tabulated", job), out.string(), cpuContext(cache.string()));
    CHECK(second.kernel->fromCache);
    CHECK(second.validation.slices.iou == first.validation.slices.iou);
}

namespace {

/// Records the beam it was given.
class BeamSpy : public planners::Planner {
public:
    explicit BeamSpy(kernel::FittedBeam* seen) : mSeen(seen) {}
    plan::Process process() const override { return plan::Process::Laser; }
    plan::ScanPlan plan(const planners::PlannerInputs& in) override {
        *mSeen = in.beam;
        return plan::emptyPlan(in.layers, in.machine);
    }

private:
    kernel::FittedBeam* mSeen;
};

}  // namespace

// Issue 23 item 3: kernel.plan is parsed with the kernel keys, the planner gets the planning
// beam and the exposure the simulated one.
TEST_CASE("a job may plan with one kernel and simulate with another", "[pipeline]") {
    auto json = givenKernelJob();
    json["kernel"]["plan"] = {{"source", "given"}, {"We3D", "80 um"}, {"De3D", "120 um"}};
    pipeline::Job job = load("plan_kernel", json);
    REQUIRE(job.kernel.plan);
    CHECK(job.kernel.plan->given.radius == Approx(0.08));
    CHECK(job.kernel.given.radius == Approx(0.06));
    const RunContext context = cpuContext();
    const pipeline::BeamResult beam = pipeline::beamStage(job, context);
    REQUIRE(beam.planBeam);
    CHECK(beam.planningBeam().attenuationLength == Approx(0.12));
    CHECK(beam.beam.attenuationLength == Approx(0.04));

    kernel::FittedBeam seen;
    pipeline::Builtins builtins = pipeline::makeBuiltins();
    builtins.planners.add({"spy", "records its beam", {{}}, [&seen](const KeyReader&) {
                               return std::make_unique<BeamSpy>(&seen);
                           }});
    json["plan"] = {{"strategy", "spy"}};
    job = load("plan_kernel_spy", json, builtins);
    const geometry::Mesh part = pipeline::partStage(job);
    const geometry::LayerStack layers = pipeline::sliceStage(job, part);
    pipeline::planStage(job, layers, part.bounds(), pipeline::beamStage(job, context), context);
    CHECK(seen.radius == Approx(0.08));
    CHECK(seen.attenuationLength == Approx(0.12));

    json = givenKernelJob();  // no nesting, and the plan kernel's keys are checked
    json["kernel"]["plan"] = {{"source", "given"}, {"We3D", "80 um"}, {"plan", {}}};
    CHECK_THROWS_WITH(load("plan_kernel_nested", json), Contains("kernel.plan.plan"));
    json["kernel"]["plan"] = {{"source", "given"}, {"We3D", "2 mW"}};
    CHECK_THROWS_WITH(load("plan_kernel_unit", json), Contains("kernel.plan.We3D"));
    json["kernel"]["plan"] = {{"source", "monte-carlo"}};
    CHECK_THROWS_WITH(load("plan_kernel_material", json), Contains("material"));
}

// Issue 23 item 2: objective exposure-l2 is the inverse planner as it was: the adapter's plan
// equals optimise::planInverse with the same parameters (the ACES start without the stack rule).
TEST_CASE("inverse with objective exposure-l2 plans as before", "[pipeline]") {
    auto json = givenKernelJob();
    json["plan"] = {{"strategy", "inverse"},
                    {"objective", "exposure-l2"},
                    {"iterations", 5},
                    {"coarse_iterations", 5}};
    const pipeline::Job job = load("inverse_l2", json);
    const RunContext context = cpuContext();
    const geometry::Mesh part = pipeline::partStage(job);
    const geometry::LayerStack layers = pipeline::sliceStage(job, part);
    const pipeline::BeamResult beam = pipeline::beamStage(job, context);
    const pipeline::PlanResult planned =
        pipeline::planStage(job, layers, part.bounds(), beam, context, &part);
    CHECK(planned.summary["inverse"]["objective"] == "exposure-l2");

    const ConfigNode section = ConfigNode(json, "job.json").child("plan");
    const KeyTable table = planners::inverseKeyTable();
    const KeyReader keys(table, section, "inverse");
    optimise::InverseParameters p = planners::readInverseParameters(keys);
    p.base.aces = planners::acesParameters(planners::readLaserPlanOptions(keys), beam.beam,
                                           job.machine, job.cure->criticalDose());
    p.base.wallOnContour = true;
    std::vector<geometry::PolygonSet> regions;
    std::vector<double> tops;
    for (const auto& layer : layers.layers) {
        regions.push_back(layer.region);
        tops.push_back(layer.zBottom + layers.layerThickness);
    }
    optimise::InverseResult direct = optimise::planInverse(regions, tops, p, beam.beam);
    // The planner then runs the plan on the machine (issue 23 item 1): the same fit here.
    const double dotSpacing =
        double(std::max(1L, std::lround(p.dotPitch / p.base.gridPitch))) * p.base.gridPitch;
    planners::fitLaserPlan(direct.plan, p.base.aces, job.machine, dotSpacing);
    REQUIRE(direct.plan.layers.size() == planned.plan.layers.size());
    for (size_t k = 0; k < direct.plan.layers.size(); ++k) {
        const auto& a = direct.plan.layers[k].points;
        const auto& b = planned.plan.layers[k].points;
        REQUIRE(a.size() == b.size());
        for (size_t i = 0; i < a.size(); ++i) {
            CHECK(a[i].x == b[i].x);
            CHECK(a[i].energy == b[i].energy);
        }
        const auto& va = direct.plan.layers[k].vectors;
        const auto& vb = planned.plan.layers[k].vectors;
        REQUIRE(va.size() == vb.size());
        for (size_t i = 0; i < va.size(); ++i) {
            CHECK(va[i].x0 == vb[i].x0);
            CHECK(va[i].power == vb[i].power);
        }
    }
}
