// `vpsim mc`: photon Monte Carlo of a beam entering a material (slab or semi-infinite); prints
// the reflected, transmitted and absorbed fractions with batch standard errors.

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"
#include "vpsim/gpu/context.h"
#include "vpsim/transport/beam_convolution.h"
#include "vpsim/transport/photon_mc.h"

namespace {

using vpsim::InputError;
using namespace vpsim::transport;

struct McOptions {
    std::string material;
    std::string photons = "100000";
    uint32_t seed = 1;
    std::string thickness;  ///< empty = semi-infinite
    double nOutside = 1.0;
    std::string beam = "pencil";
    std::string w0 = "50 um";
    std::vector<std::string> depths;
    std::string rMax = "0.5 mm", zMax = "0.5 mm";
    uint32_t bins = 100;
    std::string vdb;
    std::string voxel = "5 um";
    std::string estimator = estimatorName(McSetup{}.estimator);
    double roulette = DEFAULT_ROULETTE_THRESHOLD;
    bool directBeam = false;
    bool noControls = false;
    bool json = false;
};

double length(const std::string& text, const std::string& option) {
    return vpsim::parseQuantity(text, vpsim::dim::LENGTH, option);
}

McSetup setupFrom(const McOptions& o, const vpsim::cli::Globals& g) {
    McSetup s;
    s.optics = vpsim::optics::loadMediumOptics(o.material, g.overrides);
    s.photons = vpsim::cli::parseCount(o.photons, MAX_PHOTONS, "--photons");
    s.seed = o.seed;
    s.estimator = parseEstimator(o.estimator, "--estimator");
    s.rouletteThreshold = o.roulette;
    s.thickness = o.thickness.empty() ? 0.0 : length(o.thickness, "--thickness");
    if (!o.thickness.empty() && !(s.thickness > 0))
        throw InputError("--thickness: must be > 0 (leave it out for a semi-infinite medium)");
    s.nAbove = s.nBelow = o.nOutside;
    s.beam = o.beam == "gaussian" ? BeamShape::Gaussian : BeamShape::Pencil;
    s.w0 = length(o.w0, "--w0");
    s.beamConvolution = !o.directBeam;
    s.controlVariates = !o.noControls;
    if (!(s.w0 > 0.0 && s.w0 <= 100.0))
        throw InputError("must be in (0, 100] mm, got " + vpsim::quoteUser(o.w0), "", "--w0");
    for (const std::string& d : o.depths) s.depths.push_back(length(d, "--depths"));
    s.bins.rMax = length(o.rMax, "--r-max");
    s.bins.zMax = length(o.zMax, "--z-max");
    s.bins.rBins = s.bins.zBins = o.bins;
    if (!o.vdb.empty()) {
        s.grid.voxel = length(o.voxel, "--voxel");
        if (!(s.grid.voxel > 0)) throw InputError("--voxel: must be > 0");
        // Sized in double and checked in bytes before the uint32 casts could wrap.
        const double nxy = std::ceil(2 * s.bins.rMax / s.grid.voxel);
        const double nz = std::ceil(s.bins.zMax / s.grid.voxel);
        vpsim::checkMemory(g.hostContext(), nxy * nxy * nz * 8.0,
                           "the --vdb absorption grid at --voxel " + o.voxel,
                           "use a coarser --voxel or a smaller --r-max/--z-max");
        if (nxy > 65536 || nz > 65536)
            throw vpsim::ResourceError(
                "the --vdb absorption grid needs more than 65536 voxels "
                "along an axis: use a coarser --voxel");
        s.grid.nxy = uint32_t(nxy);
        s.grid.nz = uint32_t(nz);
    }
    return s;
}

void runMc(const McOptions& o, const vpsim::cli::Globals& g) {
    McSetup setup = setupFrom(o, g);
    McResult r = runPhotonMc(setup, vpsim::gpu::shaderContext(g.runContext()));
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
        cmd->add_option("--photons", o->photons, "photons to launch (e.g. 1e6)");
        cmd->add_option("--seed", o->seed,
                        "random seed (same seed, same result on any thread count)");
        cmd->add_option("--thickness", o->thickness,
                        "slab thickness, e.g. 0.2mm (default: semi-infinite)");
        cmd->add_option("--n-outside", o->nOutside,
                        "refractive index above (and below) the medium");
        cmd->add_option("--beam", o->beam, "beam shape at normal incidence")
            ->check(CLI::IsMember({"pencil", "gaussian"}));
        cmd->add_option("--w0", o->w0, "Gaussian beam 1/e^2 intensity radius W0, e.g. 50um");
        cmd->add_option("--depths", o->depths,
                        "depths for absorbed_within, e.g. 30um,84um (at most 4)")
            ->delimiter(',');
        cmd->add_option("--r-max", o->rMax, "radius of the (r,z) absorption tally");
        cmd->add_option("--z-max", o->zMax, "depth of the (r,z) absorption tally");
        cmd->add_option("--bins", o->bins, "bins along r and along z of the tally");
        cmd->add_option("--vdb", o->vdb,
                        "also tally a Cartesian absorption grid and save it to this .vdb file");
        cmd->add_option("--voxel", o->voxel, "voxel edge of the --vdb grid");
        cmd->add_option("--estimator", o->estimator,
                        "absorption estimator: collision (analog transport, bins by the "
                        "expected absorption at every interaction; default), track-length "
                        "(analog transport, track-length bins), implicit-track (implicit capture "
                        "and roulette, track-length tallies), implicit (MCML's: collision "
                        "tallies) or analog")
            ->check(CLI::IsMember(estimatorNames()));
        cmd->add_option("--roulette", o->roulette,
                        "implicit capture: roulette below this fraction of the launched weight");
        cmd->add_flag("--direct-beam", o->directBeam,
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
