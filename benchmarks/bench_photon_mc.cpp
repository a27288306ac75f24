// Photon Monte Carlo throughput on the seed-000 alumina slurry (Gaussian beam W0 = 50 um,
// semi-infinite, resin n = 1.45 under air): the Vulkan shader vs the CPU path (TBB, all cores)
// built from the same photon_step.glsl, in the same run. Prints JSON: photons/s and
// scatterings/s of each, their ratio, and the target of 300,000 photons/s through lavapipe on a
// 2-core machine (a classic single-threaded CPU MC code manages ~55,000/s on this case).
// Usage: bench_photon_mc [material.json] [photons]   (run from the repository root)

#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/gpu/context.h"
#include "vpsim/optics/material.h"
#include "vpsim/transport/photon_mc.h"

namespace {

nlohmann::json figures(const vpsim::transport::McResult& r) {
    return {{"backend", r.backend},
            {"photons", r.total().photons},
            {"seconds", r.seconds},
            {"photons_per_second", r.photonsPerSecond()},
            {"scatterings_per_second", r.photonsPerSecond() * r.scatteringsPerPhoton()},
            {"scatterings_per_photon", r.scatteringsPerPhoton()},
            {"diffuse_reflectance", r.diffuse().value},
            {"absorbed", r.absorbed().value},
            {"energy_balanced", r.energyBalanced()}};
}

}  // namespace

int main(int argc, char** argv) {
    using namespace vpsim::transport;
    const std::string material = argc > 1 ? argv[1] : "examples/materials/alumina-seed000.json";
    const uint64_t photons = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 2000000;
    nlohmann::json out{{"benchmark", "photon_mc"},
                       {"material", material},
                       {"cpu_cores", std::thread::hardware_concurrency()}};
    try {
        McSetup setup;
        setup.optics = vpsim::optics::loadMediumOptics(material);
        setup.beam = BeamShape::Gaussian;
        setup.w0 = 0.05;
        setup.photons = photons;
        setup.seed = 7;
        setup.bins = {0.3, 0.3, 60, 60};
        out["mua_per_mm"] = setup.optics.mua;
        out["mus_per_mm"] = setup.optics.mus;
        out["g"] = setup.optics.g;
        out["phase_table_size"] = setup.optics.inverseCdf.size();

        McResult cpu = runPhotonMcCpu(setup);
        out["cpu"] = figures(cpu);
        try {
            auto context = vpsim::gpu::Context::create();
            McSetup warm = setup;
            warm.photons = 20000;
            runPhotonMcGpu(warm, context);  // pipeline creation and first-use costs
            McResult gpu = runPhotonMcGpu(setup, context);
            out["gpu"] = figures(gpu);
            out["gpu_over_cpu"] = gpu.photonsPerSecond() / cpu.photonsPerSecond();
            // Same random streams on both: the tallies are identical unless the device's
            // log/sin/cos differ from the CPU's in the last bit somewhere along a trajectory.
            bool identical = gpu.absorbedRZ == cpu.absorbedRZ;
            for (int b = 0; b < MC_BATCHES; ++b)
                identical = identical && gpu.batches[b].diffuse == cpu.batches[b].diffuse &&
                            gpu.batches[b].scatterings == cpu.batches[b].scatterings;
            out["cpu_gpu_tallies_identical"] = identical;
            out["cpu_gpu_diffuse_reflectance_difference"] =
                gpu.diffuse().value - cpu.diffuse().value;
            out["diffuse_reflectance_stderr"] = cpu.diffuse().standardError;
            out["target_photons_per_second"] = 300000;
            out["gpu_over_target"] = gpu.photonsPerSecond() / 300000.0;
            out["classic_single_thread_reference_photons_per_second"] = 55000;
            out["gpu_over_classic_reference"] = gpu.photonsPerSecond() / 55000.0;
        } catch (const vpsim::Error& e) {
            out["gpu_error"] = e.what();
        }
    } catch (const vpsim::Error& e) {
        out["error"] = e.what();
        std::cout << out.dump(2) << std::endl;
        return 1;
    }
    std::cout << out.dump(2) << std::endl;
    return 0;
}
