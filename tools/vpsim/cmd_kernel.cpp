// `vpsim kernel`: the beam kernel of a material (seed 000 Section II-C): photon Monte Carlo of a
// Gaussian beam, intensity by Eq. 11, fit of Eq. 12, written as kernel.json, kernel.vdb and
// pictures (Fig. 11-13) into --out.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/kernel/kernel_arguments.h"
#include "vpsim/kernel/kernel_cache.h"
#include "vpsim/kernel/kernel_summary.h"
#include "vpsim/transport/photon_mc.h"

namespace {

using vpsim::InputError;
using namespace vpsim::transport;
using namespace vpsim::kernel;

struct KernelCliOptions {
    std::string material, out;
    KernelArguments arguments;
    bool json = false;
};

void runKernel(const KernelCliOptions& o, const vpsim::cli::Globals& g) {
    const KernelOptions options = kernelOptions(o.arguments, vpsim::cli::optionName);
    KernelRequest request = kernelRequest(o.material, options, g.overrides);
    const McSetup& s = request.setup;

    // The same cache as `vpsim run`: a kernel already computed for these inputs is reused.
    bool fromCache = false;
    McResult mc;
    BeamKernel k = cachedKernel(request, g.runContext(), fromCache, &mc);
    vpsim::createDirectories(o.out);
    k.save(o.out + "/kernel.json");
    writeKernelVdb(o.out + "/kernel.vdb", k);
    writeKernelFigures(o.out, k);

    nlohmann::json out = kernelSummaryJson(k, s, fromCache);
    out["kernel"] = o.out + "/kernel.json";
    if (!fromCache) out["monte_carlo"] = mc.summaryJson();
    if (o.json) {
        vpsim::cli::printJson(out);
        return;
    }
    std::printf("Beam kernel of %s (%llu photons on %s) -> %s\n", o.material.c_str(),
                static_cast<unsigned long long>(k.photons),
                fromCache ? "the kernel cache" : mc.backend.c_str(), o.out.c_str());
    const auto um = [](double mm) { return vpsim::formatQuantity(mm * 1000, "um"); };
    std::printf("  We3D  %s   (incident W0 %s)\n", um(k.fit.we3d).c_str(), um(s.w0).c_str());
    std::printf("  De3D  %s   (no scattering 1/mua = %s)\n", um(k.fit.de3d).c_str(),
                um(1 / s.optics.mua).c_str());
    std::printf("  zmax  %s   (depth of the largest Ie(0,z))\n", um(k.zmax).c_str());
    std::printf("  Ie3D(0,0) %.4g mW/mm^2 (no scattering %.4g), fit residual %.3g\n",
                k.fit.amplitude, k.beerLambert(0, 0), k.fit.residual);
    std::printf(
        "  energy: the fit (used by the engines) carries %.3g of the table's absorbed "
        "power;\n          the energy-conserving fit has Ie3D(0,0) %.4g, residual %.3g\n",
        k.fit.energyFraction, k.energyFit.amplitude, k.energyFit.residual);
}

vpsim::cli::CommandRegistration registerKernel{
    "kernel", [](CLI::App& app, const vpsim::cli::Globals& g) {
        auto* cmd = app.add_subcommand(
            "kernel", "Beam kernel I(r,z) of a material by photon Monte Carlo (Eq. 11-12)");
        auto o = std::make_shared<KernelCliOptions>();
        cmd->add_option("--material", o->material, "material JSON file")->required();
        cmd->add_option("--power", o->arguments.power, "laser power, e.g. 10mW");
        cmd->add_option("--w0", o->arguments.w0,
                        "Gaussian beam 1/e^2 intensity radius W0, e.g. 50um");
        cmd->add_option("--out", o->out, "output directory")->required();
        cmd->add_option("--photons", o->arguments.photons, "photons to launch (e.g. 1e6)");
        cmd->add_option("--seed", o->arguments.seed, "random seed");
        cmd->add_option("--thickness", o->arguments.thickness,
                        "slab thickness (default: semi-infinite)");
        cmd->add_option("--n-outside", o->arguments.nOutside,
                        "refractive index above (and below) the medium");
        cmd->add_option("--r-max", o->arguments.rMax,
                        "radius of the tabulated kernel (default 4 W0)");
        cmd->add_option("--z-max", o->arguments.zMax,
                        "depth of the tabulated kernel (default 3/mua)");
        cmd->add_option("--bins", o->arguments.bins, "bins along r and along z");
        cmd->add_option("--estimator", o->arguments.estimator,
                        "absorption estimator: collision (default), track-length, implicit-track, "
                        "implicit or analog")
            ->check(CLI::IsMember(estimatorNames()));
        cmd->add_flag("--json", o->json, "print JSON");
        cmd->callback([o, &g] { runKernel(*o, g); });
    }};

}  // namespace
