// `vpsim mie`: Lorenz-Mie scattering of one sphere (--m, --x) or the optics of a slurry material
// file (--material). Conventions (m = n - ik, Bohren & Huffman Qback) are in optics/mie.h.

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/optics/material_file.h"
#include "vpsim/optics/mie.h"
#include "vpsim/optics/mie_summary.h"
#include "vpsim/optics/phase_table.h"
#include "vpsim/plot/plot.h"

namespace {

using vpsim::InputError;
using namespace vpsim::optics;

constexpr double PI = 3.14159265358979323846;

struct MieOptions {
    std::string m;
    double x = 0.0;
    std::vector<double> angles;  ///< degrees
    std::string material;
    std::vector<double> cdfAngles;  ///< degrees
    std::string plot;               ///< SVG of the phase function
    bool json = false;
};

/// Writes log10 of the normalised phase function p(theta) (1/sr, integral over the sphere = 1)
/// per 0.1-degree panel of the table, from the CDF increments.
void writePhasePlot(const std::string& path, const PhaseTable& t, const std::string& title) {
    vpsim::plot::Curve series{"phase function"};
    for (size_t i = 0; i + 1 < t.thetaEdges.size(); ++i) {
        const double t0 = t.thetaEdges[i], t1 = t.thetaEdges[i + 1];
        const double solidAngle = 2.0 * PI * (std::cos(t0) - std::cos(t1));
        const double p = (t.cdf[i + 1] - t.cdf[i]) / solidAngle;
        if (!(p > 0.0)) continue;
        series.x.push_back(0.5 * (t0 + t1) * 180.0 / PI);
        series.y.push_back(p);
    }
    vpsim::plot::LineFigure figure{title, "scattering angle (deg)", "p(#gh) (1/sr)", {series}};
    figure.logY = true;
    vpsim::plot::writeLineFigure(vpsim::plot::figureStem(path), figure);
}

void printSphereTable(const nlohmann::json& out) {
    std::printf(
        "  Qext  %.7g\n  Qsca  %.7g\n  Qabs  %.7g\n  Qback %.7g  (Bohren & Huffman, "
        "4|S1(180)|^2/x^2)\n"
        "  g     %.7g\n  terms %d\n",
        out["qext"].get<double>(), out["qsca"].get<double>(), out["qabs"].get<double>(),
        out["qback"].get<double>(), out["g"].get<double>(), out["terms"].get<int>());
    if (!out.contains("s1")) return;
    std::printf("  %9s %14s %14s %14s %14s\n", "angle", "Re S1", "Im S1", "Re S2", "Im S2");
    for (size_t i = 0; i < out["s1"].size(); ++i)
        std::printf("  %9.3f %14.6e %14.6e %14.6e %14.6e\n", out["angles_deg"][i].get<double>(),
                    out["s1"][i][0].get<double>(), out["s1"][i][1].get<double>(),
                    out["s2"][i][0].get<double>(), out["s2"][i][1].get<double>());
}

void runSphere(const MieOptions& o) {
    if (o.m.empty() || o.x == 0.0)
        throw InputError("mie: give both --m and --x, or --material FILE");
    if (!o.cdfAngles.empty()) throw InputError("mie: --cdf-angles needs --material");
    Complex m = parseRefractiveIndex(o.m, "--m");
    nlohmann::json out = mieSphereJson(m, o.x, o.angles);
    if (!o.plot.empty()) {
        writePhasePlot(o.plot, miePhaseTable(mieCoefficients(m, o.x)),
                       "Mie phase function, x = " + vpsim::formatQuantity(o.x) +
                           ", m = " + formatRefractiveIndex(m));
        out["plot"] = o.plot;
    }
    if (o.json) {
        vpsim::cli::printJson(out);
        return;
    }
    std::printf("Mie sphere x = %g, m = %s (convention m = n - ik)\n", o.x,
                formatRefractiveIndex(m).c_str());
    printSphereTable(out);
}

void runMaterial(const MieOptions& o, const vpsim::cli::Globals& g) {
    if (!o.m.empty() || o.x != 0.0)
        throw InputError("mie: --material cannot be combined with --m/--x");
    MaterialDefinition material = loadMaterialDefinition(o.material, g.overrides);
    SlurryOptics s = computeSlurryOptics(material);
    nlohmann::json out = slurryOpticsJson(s, o.angles, o.cdfAngles);
    out["material"] = o.material;
    if (!o.plot.empty()) {
        writePhasePlot(o.plot, s.phase, "Phase function of " + o.material);
        out["plot"] = o.plot;
    }
    if (o.json) {
        vpsim::cli::printJson(out);
        return;
    }
    std::printf("Slurry %s: x = %.6g, m = %s (m = n - ik)\n", o.material.c_str(), s.x,
                formatRefractiveIndex(s.m).c_str());
    printSphereTable(out);
    std::printf("  scattering mean free path  %.6g um (mus = %.6g /mm)\n",
                out["scattering_mean_free_path_um"].get<double>(), s.medium.mus);
    std::printf("  transport mean free path   %.6g um\n",
                out["transport_mean_free_path_um"].get<double>());
    std::printf("  absorption mua             %.6g /mm\n", s.medium.mua);
    std::printf("  phase table                %zu entries, mean cosine %.6g\n",
                s.phase.inverseCdf.size(), s.phase.tableMeanCosine());
    for (size_t i = 0; i < o.cdfAngles.size(); ++i)
        std::printf("  CDF(%g deg) = %.6g\n", o.cdfAngles[i], out["cdf"][i].get<double>());
}

vpsim::cli::CommandRegistration registerMie{
    "mie", [](CLI::App& app, const vpsim::cli::Globals& g) {
        auto* cmd =
            app.add_subcommand("mie", "Lorenz-Mie scattering of a sphere or a slurry material");
        auto o = std::make_shared<MieOptions>();
        cmd->add_option(
            "--m", o->m,
            "relative refractive index n-ki, e.g. 1.5-0.1i (absorbing: negative imaginary part)");
        cmd->add_option("--x", o->x, "size parameter 2 pi r n_medium / lambda0");
        cmd->add_option("--angles", o->angles,
                        "scattering angles for S1, S2, degrees (comma-separated)")
            ->delimiter(',');
        cmd->add_option("--material", o->material, "slurry material JSON file");
        cmd->add_option("--cdf-angles", o->cdfAngles,
                        "angles at which to print the phase CDF, degrees")
            ->delimiter(',');
        cmd->add_option("--plot", o->plot, "write the phase function to FILE.svg (and FILE.png)");
        cmd->add_flag("--json", o->json, "print JSON");
        cmd->callback([o, &g] {
            checkAngles(o->angles, "--angles");
            checkAngles(o->cdfAngles, "--cdf-angles");
            if (!o->material.empty())
                runMaterial(*o, g);
            else
                runSphere(*o);
        });
    }};

}  // namespace
