#include "vpsim/pipeline/job.h"

#include <filesystem>

#include "vpsim/core/checks.h"
#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/plan/scan_report.h"

namespace vpsim::pipeline {
namespace {

SimulationSpec simulationFromConfig(const ConfigNode& sim) {
    SimulationSpec spec;
    spec.voxel = positiveQuantity(sim, "voxel", dim::LENGTH, 0.01);
    spec.slicesPerLayer = int(sim.integer("slices_per_layer", 5));
    if (spec.slicesPerLayer < 1 || spec.slicesPerLayer > 100)
        throw sim.error("slices_per_layer", "expected 1 .. 100");
    spec.margin = sim.quantity("margin", dim::LENGTH, -1.0);
    spec.writeVdb = sim.boolean("write_vdb", true);
    return spec;
}

/// The section `key` of `root`, or an empty one (so defaults apply) when it is absent.
ConfigNode sectionOrEmpty(const ConfigNode& root, const std::string& key) {
    return root.has(key) ? root.child(key) : ConfigNode(nlohmann::json::object(), root.file());
}

void createPlanner(const ConfigNode& root, const Builtins& builtins, Job& job) {
    ConfigNode plan = root.child("plan");
    job.strategy = plan.choice("strategy", builtins.planners.names());
    job.planner = builtins.planners.create(job.strategy, plan);
    if (job.planner->process() != job.machine.process)
        throw root.error("plan.strategy", "'" + job.strategy + "' plans a " +
                                              plan::processName(job.planner->process()) +
                                              " process, but machine.process is " +
                                              plan::processName(job.machine.process));
}

}  // namespace

Job loadJob(const std::string& path, const Builtins& builtins,
            const std::vector<std::string>& overrides) {
    ConfigNode root = ConfigNode::load(path, overrides);
    Job job;
    job.file = path;
    job.name = root.string("name", std::filesystem::path(path).stem().string());
    root.string("description", std::string());
    job.cure = cure::cureLawFromConfig(builtins.cureLaws, root, "cure");
    job.part = geometry::partSpecFromConfig(root.child("part"));
    job.machine = plan::machineFromConfig(root.child("machine"));
    if (root.has("material")) job.materialFile = resolvePath(root, "material");
    job.kernel = kernel::kernelSpecFromConfig(sectionOrEmpty(root, "kernel"));
    const bool laser = job.machine.process == plan::Process::Laser;
    if (laser && job.kernel.source == kernel::KernelSource::MonteCarlo && job.materialFile.empty())
        throw root.error("material", "a Monte Carlo kernel needs a material file");
    if (!laser && !job.cure->hasPenetrationDepth())
        throw root.error("cure",
                         "a DLP job needs the resin's penetration depth "
                         "(cure.penetration_depth or cure.attenuation)");
    createPlanner(root, builtins, job);
    if (laser) job.scanOrder = plan::orderMethodFromConfig(root.child("plan"));
    job.simulation = simulationFromConfig(sectionOrEmpty(root, "simulation"));
    if (root.has("features"))
        job.features = validate::featureProbesFromConfig(root.children("features"));
    root.checkUnknownKeys();
    return job;
}

}  // namespace vpsim::pipeline
