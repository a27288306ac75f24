#include "vpsim/pipeline/job.h"

#include <algorithm>
#include <filesystem>

#include "vpsim/core/checks.h"
#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/text.h"

namespace vpsim::pipeline {

const std::vector<std::string> OUTPUT_NAMES{"cured.stl", "exposure.vdb", "reference.vdb", "figures",
                                            "viewer"};

namespace {

SimulationSpec simulationFromConfig(const ConfigNode& sim) {
    SimulationSpec spec;
    spec.voxel = positiveQuantity(sim, "voxel", dim::LENGTH, 0.01);
    spec.slicesPerLayer = int(sim.integer("slices_per_layer", 5));
    if (spec.slicesPerLayer < 1 || spec.slicesPerLayer > 100)
        throw sim.error("slices_per_layer", "expected 1 .. 100");
    spec.margin = sim.quantity("margin", dim::LENGTH, -1.0);
    spec.writeVdb = sim.boolean("write_vdb", true);
    if (!spec.writeVdb) {
        spec.outputs.erase("exposure.vdb");
        spec.outputs.erase("reference.vdb");
    }
    if (sim.has("outputs")) {
        const nlohmann::json& list = sim.raw("outputs");
        if (!list.is_array()) throw sim.error("outputs", "expected a list of output names");
        spec.outputs.clear();
        for (const nlohmann::json& name : list) {
            if (!name.is_string() || std::find(OUTPUT_NAMES.begin(), OUTPUT_NAMES.end(),
                                               name.get<std::string>()) == OUTPUT_NAMES.end())
                throw sim.error("outputs", "unknown output " + name.dump() + "; expected " +
                                               "cured.stl, exposure.vdb, reference.vdb, "
                                               "figures or viewer");
            spec.outputs.insert(name.get<std::string>());
        }
        // write_vdb beside outputs (a job overriding only one of them) must say the same.
        if (sim.has("write_vdb") && spec.writeVdb != spec.writes("exposure.vdb"))
            throw sim.error("write_vdb", std::string("says ") + (spec.writeVdb ? "true" : "false") +
                                             " but outputs " +
                                             (spec.writeVdb ? "leaves out" : "lists") +
                                             " exposure.vdb; give one of them");
        spec.writeVdb = spec.writes("exposure.vdb");
    }
    if (sim.has("tile") && !(sim.raw("tile").is_string() && sim.string("tile") == "auto"))
        spec.tile = positiveQuantity(sim, "tile", dim::LENGTH, 0.0);
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

/// Without an `export` section every registered exporter runs that can be created from the
/// machine's projector calibration (grey_levels, exposure_time: the keys it documents); one that
/// needs more options is skipped with a debug line (nobody asked for it: a laser job has no
/// projector, and saying so on every run is noise).
void createExporters(const ConfigNode& root, const Builtins& builtins, Job& job) {
    if (!root.has("export")) {
        const ConfigNode machine = root.child("machine");
        for (const auto& [name, entry] : builtins.exporters.entries()) {
            nlohmann::json options = nlohmann::json::object();
            for (const KeySpec& key : entry.keys.keys())
                if (machine.has(key.name)) options[key.name] = machine.raw(key.name);
            try {
                job.exporters.emplace_back(
                    name, builtins.exporters.create(name, ConfigNode(options, root.file())));
            } catch (const InputError& e) {
                logDebug("exporter " + name + " not run: " + std::string(e.what()) +
                         " (give its options in the job's export section)");
            }
        }
        return;
    }
    ConfigNode section = root.child("export");
    for (const std::string& name : section.keys()) {
        ConfigNode options = section.child(name);
        try {
            job.exporters.emplace_back(name, builtins.exporters.create(name, options));
        } catch (const InputError& e) {
            if (builtins.exporters.has(name)) throw;
            throw section.error(name, e.reason());  // an unknown exporter, named with its key
        }
    }
}

/// Lengths that must resolve against each other: light that dies within one voxel slice cannot
/// be sampled (the exposure overflows to +inf), and a voxel coarser than the beam cannot draw it.
void checkScales(const ConfigNode& root, const Job& job) {
    const double voxelHeight = job.machine.layerThickness / job.simulation.slicesPerLayer;
    const double depth = job.cure->penetrationDepth();
    if (depth > 0.0 && depth < voxelHeight)
        throw root.error("cure.penetration_depth",
                         "penetration depth " + formatQuantity(depth * 1000.0) +
                             " um is shorter than a voxel slice (" +
                             formatQuantity(voxelHeight * 1000.0) +
                             " um = layer thickness / slices_per_layer): raise slices_per_layer "
                             "or check the unit");
    if (job.simulation.voxel > 10.0)
        throw root.error("simulation.voxel", "must be at most 10 mm, got " +
                                                 formatQuantity(job.simulation.voxel) + " mm");
    if (job.machine.layerThickness > 10.0)
        throw root.error(
            "machine.layer_thickness",
            "must be at most 10 mm, got " + formatQuantity(job.machine.layerThickness) + " mm");
}

}  // namespace

Job loadJob(const std::string& path, const Builtins& builtins,
            const std::vector<std::string>& overrides) {
    return loadJob(ConfigNode::load(path, overrides), builtins);
}

Job loadJob(const ConfigNode& root, const Builtins& builtins,
            std::shared_ptr<const geometry::Mesh> part) {
    const std::string& path = root.file();
    Job job;
    job.file = path;
    job.document = root.json();
    job.name = root.string("name", std::filesystem::path(path).stem().string());
    root.string("description", std::string());
    job.cure = cure::cureLawFromConfig(builtins.cureLaws, root, "cure");
    if (part && root.has("part"))
        throw root.error("part", "the part is given as arrays: leave the part section out");
    if (part)
        job.part.mesh = std::move(part);
    else
        job.part = geometry::partSpecFromConfig(root.child("part"));
    job.machine = plan::machineFromConfig(root.child("machine"));
    if (root.has("material")) job.materialFile = resolvePath(root, "material");
    job.kernel = kernel::kernelSpecFromConfig(sectionOrEmpty(root, "kernel"));
    const bool laser = job.machine.process == plan::Process::Laser;
    if (laser && job.kernel.source == kernel::KernelSource::MonteCarlo && job.materialFile.empty())
        throw root.error("material", "a Monte Carlo kernel needs a material file");
    if (laser && job.kernel.plan && job.kernel.plan->source == kernel::KernelSource::MonteCarlo &&
        job.materialFile.empty())
        throw root.error("material",
                         "a Monte Carlo planning kernel (kernel.plan) needs a "
                         "material file");
    if (!laser && job.kernel.plan)
        throw root.error("kernel", "kernel.plan is for laser jobs (a DLP job has no kernel)");
    if (!laser && !job.cure->hasPenetrationDepth())
        throw root.error("cure",
                         "a DLP job needs the resin's penetration depth "
                         "(cure.penetration_depth or cure.attenuation)");
    createPlanner(root, builtins, job);
    if (laser) job.scanOrder = job.planner->partOrder();
    job.simulation = simulationFromConfig(sectionOrEmpty(root, "simulation"));
    createExporters(root, builtins, job);
    checkScales(root, job);
    if (root.has("features"))
        job.features = validate::featureProbesFromConfig(root.children("features"));
    root.checkUnknownKeys();
    return job;
}

std::vector<std::string> jobInputFiles(const Job& job) {
    std::vector<std::string> files;  // every resolvePath of loadJob and its sections
    if (!job.materialFile.empty()) files.push_back(job.materialFile);
    if (!job.part.mesh && !job.part.stl.empty()) files.push_back(job.part.stl);
    return files;
}

}  // namespace vpsim::pipeline
