// Beam kernels from the photon Monte Carlo, cached on disk by a hash of everything they depend on.
#include "vpsim/kernel/kernel_cache.h"

#include <cstdio>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "vpsim/cluster/communicator.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/log.h"
#include "vpsim/gpu/context.h"
#include "vpsim/optics/material.h"
#include "vpsim/transport/mc_split.h"

namespace vpsim::kernel {
namespace {

/// FNV-1a, 64-bit: a stable hash of the kernel's inputs (file contents and numbers as text).
uint64_t fnv1a(const std::string& text) {
    uint64_t hash = 1469598103934665603ull;
    for (unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
    return hash;
}

std::string cacheKey(const KernelRequest& r) {
    const transport::McSetup& s = r.setup;
    nlohmann::json key{
        {"material", readFile(r.materialFile)},
        {"optics", {s.optics.mua, s.optics.mus, s.optics.g, s.optics.refractiveIndex}},
        {"power", r.power},
        {"w0", s.w0},
        {"photons", s.photons},
        {"seed", s.seed},
        {"thickness", s.thickness},
        {"n_outside", {s.nAbove, s.nBelow}},
        {"r_max", s.bins.rMax},
        {"z_max", s.bins.zMax},
        {"bins", {s.bins.rBins, s.bins.zBins}},
        {"estimator", transport::estimatorName(s.estimator)},
        {"roulette_threshold", s.rouletteThreshold},
        // 3: sub-bin zmax (0 when Ie(0,z) falls from the surface), fit energies, track-length
        // estimator by default (issue 14).
        {"version", 3}};
    char name[64];
    std::snprintf(name, sizeof name, "kernel-%016llx.json", (unsigned long long)fnv1a(key.dump()));
    return name;
}

/// The kernel stored at `path`, or nothing when there is none (or it cannot be read: recomputed).
std::optional<BeamKernel> loadCached(const std::string& path) {
    std::error_code unreadable;
    if (path.empty() || !std::filesystem::exists(path, unreadable)) return std::nullopt;
    try {
        return BeamKernel::load(path);
    } catch (const Error& e) {
        logWarn("ignoring unreadable cached kernel " + path + ": " + e.what());
        return std::nullopt;
    }
}

}  // namespace

KernelRequest kernelRequest(const std::string& materialFile, double power, double w0,
                            uint64_t photons, uint32_t seed,
                            const std::vector<std::string>& overrides) {
    const optics::MediumOptics medium = optics::loadMediumOptics(materialFile, overrides);
    if (!(medium.mua > 0))
        throw InputError(
            "the beam kernel needs an absorbing material (mua > 0): Eq. 11 divides by mua",
            materialFile, "mua");
    KernelRequest request;
    request.materialFile = materialFile;
    request.power = power;
    request.setup = kernelSetup(medium, w0);
    request.setup.photons = photons;
    request.setup.seed = seed;
    return request;
}

BeamKernel cachedKernel(const KernelRequest& request, const RunContext& context, bool& fromCache,
                        transport::McResult* monteCarlo) {
    if (!(request.setup.optics.mua > 0))
        throw InputError("the beam kernel needs an absorbing material (mua > 0)",
                         request.materialFile, "mua");
    const std::string dir = context.cacheDirectory;
    const std::string path = dir.empty() ? "" : dir + "/" + cacheKey(request);
    cluster::SingleProcess single;
    cluster::Communicator& comm = context.cluster ? *context.cluster : single;
    // Rank 0 reads the cache and the other ranks take its kernel, so that all make the same
    // collective calls (the Monte Carlo below, or none) and hold the same kernel.
    std::optional<BeamKernel> cached;
    if (comm.isRoot()) cached = loadCached(path);
    if (comm.ranks() > 1) {
        const std::string text = comm.broadcastBytes(cached ? cached->toJson().dump() : "");
        if (!comm.isRoot() && !text.empty())
            cached = BeamKernel::fromJson(nlohmann::json::parse(text), path);
    }
    fromCache = cached.has_value();
    if (cached) return *cached;
    transport::McResult mc =
        transport::runPhotonMcSplit(request.setup, gpu::monteCarloContext(context), comm);
    BeamKernel beam = kernelFromMonteCarlo(mc, request.power);
    if (monteCarlo) *monteCarlo = mc;
    if (path.empty() || !comm.isRoot()) return beam;
    try {
        createDirectories(dir);
        beam.save(path);
    } catch (const Error& e) {
        logWarn(std::string("could not cache the beam kernel: ") + e.what());
    }
    return beam;
}

std::string defaultKernelCacheDirectory(const char* vpsimCacheDir, const char* xdgCacheHome,
                                        const char* home) {
    if (vpsimCacheDir && *vpsimCacheDir) return vpsimCacheDir;
    if (xdgCacheHome && *xdgCacheHome) return std::string(xdgCacheHome) + "/vpsim";
    if (home && *home) return std::string(home) + "/.cache/vpsim";
    return ".vpsim-cache";
}

}  // namespace vpsim::kernel
