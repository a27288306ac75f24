#include "vpsim/report/job.h"

#include <filesystem>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"

namespace vpsim::report {
namespace {

std::string resolve(const ConfigNode& node, const std::string& key) {
    std::filesystem::path path = node.string(key);
    if (path.is_relative()) path = std::filesystem::path(node.file()).parent_path() / path;
    if (!std::filesystem::exists(path)) throw node.error(key, "file not found: " + path.string());
    return path.string();
}

double positive(const ConfigNode& node, const std::string& key, Dimension dimension,
                double fallback) {
    double value = node.quantity(key, dimension, fallback);
    if (!(value > 0)) throw node.error(key, "must be positive");
    return value;
}

void readPart(const ConfigNode& part, Job& job) {
    if (part.has("stl") == part.has("test_part"))
        throw part.error("stl", "give exactly one of 'stl' or 'test_part'");
    if (part.has("stl")) {
        job.partStl = resolve(part, "stl");
        job.partScale = part.number("scale", 1.0);
        return;
    }
    job.testPart = part.choice("test_part", geometry::testPartNames());
    auto& o = job.testPartOptions;
    if (part.has("size")) o.size = positive(part, "size", dim::LENGTH, 1);
    if (part.has("height")) o.height = positive(part, "height", dim::LENGTH, 1);
    if (part.has("top_size")) o.topSize = positive(part, "top_size", dim::LENGTH, 1);
    if (part.has("depth")) o.depth = positive(part, "depth", dim::LENGTH, 1);
    if (part.has("spacing")) o.spacing = positive(part, "spacing", dim::LENGTH, 1);
    if (part.has("count")) o.count = int(part.integer("count"));
    if (part.has("segments")) o.segments = int(part.integer("segments"));
}

void readKernel(const ConfigNode& kernel, Job& job) {
    std::string source =
        kernel.choice("source", {"monte-carlo", "given"}, std::string("monte-carlo"));
    if (source == "monte-carlo") {
        job.kernelSource = KernelSource::MonteCarlo;
        long long photons = kernel.integer("photons", 300000);
        if (photons < 1000 || photons > 4000000000LL)
            throw kernel.error("photons", "expected 1000 .. 4e9");
        job.photons = uint64_t(photons);
        job.seed = uint32_t(kernel.integer("seed", 1));
        job.tabulatedKernel =
            kernel.choice("use", {"fitted", "tabulated"}, std::string("fitted")) == "tabulated";
    } else {
        job.kernelSource = KernelSource::Given;
        job.givenWe3d = positive(kernel, "We3D", dim::LENGTH, 0.05);
        job.givenDe3d = positive(kernel, "De3D", dim::LENGTH, 0.1);
        job.givenZmax = kernel.quantity("zmax", dim::LENGTH, 0.0);
        job.givenEfficiency = kernel.numberInRange("efficiency", 1e-6, 10.0, 1.0);
    }
}

void readPlan(const ConfigNode& plan, Job& job) {
    std::string strategy = plan.choice("strategy", {"aces", "uniform-mask"});
    job.strategy = strategy == "aces" ? PlanStrategy::Aces : PlanStrategy::UniformMask;
    if (job.strategy == PlanStrategy::Aces) {
        job.homogeneity = plan.numberInRange("homogeneity", 1e-6, 0.5, 0.01);
        job.edgeFivePercent = plan.choice("edge", {"seed-5-percent", "cure-at-contour"},
                                          std::string("seed-5-percent")) == "seed-5-percent";
    } else {
        job.maskDose = positive(plan, "dose", dim::DOSE, 0.78);
        job.greyscaleMask = plan.boolean("greyscale", false);
    }
}

}  // namespace

Job loadJob(const std::string& path, const std::vector<std::string>& overrides) {
    ConfigNode root = ConfigNode::load(path, overrides);
    Job job;
    job.file = path;
    job.name = root.string("name", std::filesystem::path(path).stem().string());
    root.string("description", std::string());
    job.cure = cure::cureModelFromConfig(root, "cure");
    readPart(root.child("part"), job);

    ConfigNode machine = root.child("machine");
    std::string process = machine.choice("process", {"laser", "dlp"}, std::string("laser"));
    job.process = process == "laser" ? Process::Laser : Process::Dlp;
    job.layerThickness = positive(machine, "layer_thickness", dim::LENGTH, 0.05);
    if (job.process == Process::Laser) {
        job.laserPower = positive(machine, "laser_power", dim::POWER, 10.0);
        job.beamRadius = positive(machine, "beam_radius", dim::LENGTH, 0.05);
    } else {
        job.pixelPitch = positive(machine, "pixel_pitch", dim::LENGTH, 0.0625);
        job.beamRadius = positive(machine, "blur_radius", dim::LENGTH, 0.02);
    }

    if (root.has("material")) job.materialFile = resolve(root, "material");
    readKernel(
        root.has("kernel") ? root.child("kernel") : ConfigNode(nlohmann::json::object(), path),
        job);
    if (job.process == Process::Laser && job.kernelSource == KernelSource::MonteCarlo &&
        job.materialFile.empty())
        throw root.error("material", "a Monte Carlo kernel needs a material file");
    readPlan(root.child("plan"), job);
    if (job.process == Process::Laser && job.strategy != PlanStrategy::Aces)
        throw root.error("plan.strategy", "a laser process needs the 'aces' strategy");
    if (job.process == Process::Dlp && job.strategy != PlanStrategy::UniformMask)
        throw root.error("plan.strategy", "a DLP process needs the 'uniform-mask' strategy");

    if (root.has("simulation")) {
        ConfigNode sim = root.child("simulation");
        job.voxel = positive(sim, "voxel", dim::LENGTH, 0.01);
        job.slicesPerLayer = int(sim.integer("slices_per_layer", 5));
        if (job.slicesPerLayer < 1 || job.slicesPerLayer > 100)
            throw sim.error("slices_per_layer", "expected 1 .. 100");
        job.margin = sim.quantity("margin", dim::LENGTH, -1.0);
        job.writeVdb = sim.boolean("write_vdb", true);
    }
    if (root.has("features"))
        for (const ConfigNode& f : root.children("features")) {
            validate::FeatureProbe probe;
            probe.name = f.string("name");
            probe.x = f.quantity("x", dim::LENGTH);
            probe.y = f.quantity("y", dim::LENGTH);
            probe.zMin = f.quantity("z_min", dim::LENGTH);
            probe.zMax = f.quantity("z_max", dim::LENGTH);
            probe.gap = f.choice("kind", {"gap", "solid"}) == "gap";
            probe.objective = f.quantity("objective", dim::LENGTH);
            if (f.has("measured"))
                for (const auto& m : f.raw("measured")) {
                    if (!m.is_number())
                        throw f.error("measured", "expected a list of lengths in mm");
                    probe.measured.push_back(m.get<double>());
                }
            job.features.push_back(probe);
        }
    root.checkUnknownKeys();
    return job;
}

}  // namespace vpsim::report
