// `vpsim mc`: photon Monte Carlo of a beam entering a material (slab or semi-infinite); prints
// the reflected, transmitted and absorbed fractions with batch standard errors.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "vpsim/core/text.h"
#include "vpsim/gpu/context.h"
#include "vpsim/transport/beam_convolution.h"
#include "vpsim/transport/mc_arguments.h"
#include "vpsim/transport/photon_mc.h"

namespace {

using namespace vpsim::transport;

struct McOptions {
    std::string material;
    McArguments arguments;
    std::string vdb;
    std::string voxel = "5 um";  ///< of the --vdb grid
    bool noControls = false;
    bool json = false;
};

McSetup setupFrom(const McOptions& o, const vpsim::cli::Globals& g) {
    McArguments a = o.arguments;
    a.controlVariates = !o.noControls;
    a.voxel = o.vdb.empty() ? "" : o.voxel;
    return mcSetup(a, vpsim::optics::loadMediumOptics(o.material, g.overrides),
                   vpsim::cli::optionName, g.hostContext());
}

void runMc(const McOptions& o, const vpsim::cli::Globals& g) {
    McSetup setup = setupFrom(o, g);
    McResult r = runPhotonMc(setup, vpsim::gpu::monteCarloContext(g.runContext()));
    if (!o.vdb.empty()) writeAbsorptionVdb(o.vdb, r);
    nlohmann::json out = r.summaryJson();
    out["material"] = o.material;
    out["seed"] = setup.seed;
    out["thickness_mm"] =
        setup.thickness > 0 ? nlohmann::json(setup.thickness) : nlohmann::json("semi-infinite");
    if (o.json) {
        vpsim::cli::printJson(out);
        return;
    }
    char medium[64] = "semi-infinite";
    if (setup.thickness > 0) std::snprintf(medium, sizeof medium, "slab %g mm", setup.thickness);
    std::printf("Photon Monte Carlo: %s, %llu photons, seed %u, %s, on %s\n", o.material.c_str(),
                static_cast<unsigned long long>(r.total().photons), setup.seed, medium,
                r.backend.c_str());
    auto line = [](const char* name, Fraction f) {
        std::printf("  %-26s %s +- %s\n", name, vpsim::formatQuantity(f.value, "", 6).c_str(),
                    vpsim::formatQuantity(f.standardError, "", 2).c_str());
    };
    line("specular reflectance", r.specular());
    line("diffuse reflectance", r.diffuse());
    line("transmittance", r.transmitted());
    line("absorbed", r.absorbed());
    for (size_t k = 0; k < setup.depths.size(); ++k) {
        char name[64];
        std::snprintf(name, sizeof name, "absorbed above %g um", setup.depths[k] * 1000);
        line(name, r.absorbedWithin(k));
    }
    if (setup.estimator == Estimator::Implicit || setup.estimator == Estimator::ImplicitTrack)
        line("roulette net (gain - loss)", r.rouletteNet());
    std::printf("  %-26s %s%s\n", "estimator", estimatorName(setup.estimator),
                r.controlled() ? " (with control variates)" : "");
    if (convolvesBeam(setup))
        std::printf("  %-26s %s\n", "(r,z) bins", "pencil response convolved with the beam");
    std::printf("  %-26s %.4g\n  %-26s %.4g\n  %-26s %.4g\n", "scatterings/photon",
                r.scatteringsPerPhoton(), "interactions/photon", r.interactionsPerPhoton(),
                "photons/s", r.photonsPerSecond());
}

vpsim::cli::CommandRegistration registerMc{
    "mc", [](CLI::App& app, const vpsim::cli::Globals& g) {
        auto* cmd =
            app.add_subcommand("mc", "Photon Monte Carlo of a beam entering a turbid material");
        auto o = std::make_shared<McOptions>();
        cmd->add_option("--material", o->material,
                        "material JSON file (slurry or plain optics form)")
            ->required();
        cmd->add_option("--photons", o->arguments.photons, "photons to launch (e.g. 1e6)");
        cmd->add_option("--seed", o->arguments.seed,
                        "random seed (same seed, same result on any thread count)");
        cmd->add_option("--thickness", o->arguments.thickness,
                        "slab thickness, e.g. 0.2mm (default: semi-infinite)");
        cmd->add_option("--n-outside", o->arguments.nOutside,
                        "refractive index above (and below) the medium");
        cmd->add_option("--beam", o->arguments.beam, "beam shape at normal incidence")
            ->check(CLI::IsMember({"pencil", "gaussian"}));
        cmd->add_option("--w0", o->arguments.w0,
                        "Gaussian beam 1/e^2 intensity radius W0, e.g. 50um");
        cmd->add_option("--depths", o->arguments.depths,
                        "depths for absorbed_within, e.g. 30um,84um (at most 4)")
            ->delimiter(',');
        cmd->add_option("--r-max", o->arguments.rMax, "radius of the (r,z) absorption tally");
        cmd->add_option("--z-max", o->arguments.zMax, "depth of the (r,z) absorption tally");
        cmd->add_option("--bins", o->arguments.bins, "bins along r and along z of the tally");
        cmd->add_option("--vdb", o->vdb,
                        "also tally a Cartesian absorption grid and save it to this .vdb file");
        cmd->add_option("--voxel", o->voxel, "voxel edge of the --vdb grid");
        cmd->add_option("--estimator", o->arguments.estimator,
                        "absorption estimator: collision (analog transport, bins by the "
                        "expected absorption at every interaction; default), track-length "
                        "(analog transport, track-length bins), implicit-track (implicit capture "
                        "and roulette, track-length tallies), implicit (MCML's: collision "
                        "tallies) or analog")
            ->check(CLI::IsMember(estimatorNames()));
        cmd->add_option("--roulette", o->arguments.roulette,
                        "implicit capture: roulette below this fraction of the launched weight");
        cmd->add_flag("--direct-beam", o->arguments.directBeam,
                      "Gaussian beam: launch photons at their offsets instead of convolving the "
                      "pencil response with the beam (same expected bins, more variance)");
        cmd->add_flag(
            "--no-control-variates", o->noControls,
            "collision and track-length estimators: report the plain reflectance, "
            "transmittance and depth tallies instead of the control-variate "
            "estimates (same bins, about a third less time, several times more variance)");
        cmd->add_flag("--json", o->json, "print JSON");
        cmd->callback([o, &g] { runMc(*o, g); });
    }};

}  // namespace
