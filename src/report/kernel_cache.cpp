// Beam kernels from the photon Monte Carlo, cached on disk by a hash of everything they depend on.
#include "report/kernel_cache.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/log.h"
#include "vpsim/optics/material.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim::report {
namespace {

/// FNV-1a, 64-bit: a stable hash of the kernel's inputs (file contents and numbers as text).
uint64_t fnv1a(const std::string& text) {
    uint64_t hash = 1469598103934665603ull;
    for (unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
    return hash;
}

}  // namespace

std::string kernelCacheDirectory() {
    if (const char* dir = std::getenv("VPSIM_CACHE_DIR")) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME")) return std::string(xdg) + "/vpsim";
    if (const char* home = std::getenv("HOME")) return std::string(home) + "/.cache/vpsim";
    return ".vpsim-cache";
}

kernel::BeamKernel monteCarloKernel(const Job& job, const std::shared_ptr<gpu::Context>& context,
                                    bool& fromCache) {
    const optics::MediumOptics medium = optics::loadMediumOptics(job.materialFile);
    if (!(medium.mua > 0))
        throw InputError("the beam kernel needs an absorbing material (mua > 0)", job.materialFile,
                         "mua");
    transport::McSetup setup = kernel::kernelSetup(medium, job.beamRadius);
    setup.photons = job.photons;
    setup.seed = job.seed;

    nlohmann::json key{{"material", readFile(job.materialFile)},
                       {"power", job.laserPower},
                       {"w0", setup.w0},
                       {"photons", setup.photons},
                       {"seed", setup.seed},
                       {"r_max", setup.bins.rMax},
                       {"z_max", setup.bins.zMax},
                       {"bins", setup.bins.rBins},
                       {"version", 1}};
    char name[64];
    std::snprintf(name, sizeof name, "kernel-%016llx.json", (unsigned long long)fnv1a(key.dump()));
    std::string path = kernelCacheDirectory() + "/" + name;
    if (std::filesystem::exists(path)) {
        try {
            fromCache = true;
            return kernel::BeamKernel::load(path);
        } catch (const Error& e) {
            logWarn("ignoring unreadable cached kernel " + path + ": " + e.what());
        }
    }
    fromCache = false;
    transport::McResult mc = transport::runPhotonMc(setup, context);
    kernel::BeamKernel beam = kernel::kernelFromMonteCarlo(mc, job.laserPower);
    try {
        createDirectories(kernelCacheDirectory());
        beam.save(path);
    } catch (const Error& e) {
        logWarn(std::string("could not cache the beam kernel: ") + e.what());
    }
    return beam;
}

}  // namespace vpsim::report
