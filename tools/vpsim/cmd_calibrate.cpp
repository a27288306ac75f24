// `vpsim calibrate`: fits the cure model to working-curve measurements (seed 001 Section 2.2):
// penetration depth Dp and critical dose Ec from Cd = Dp ln(E0/Ec), and with --gel-point the FPP
// rate constant K = ln(1/(1-Phi_c))/Ec, each with its standard error (cure/calibration.h).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/text.h"
#include "vpsim/cure/calibration.h"
#include "vpsim/pipeline/builtins.h"
#include "vpsim/pipeline/calibration_report.h"
#include "vpsim/plot/plot.h"

namespace {

using vpsim::InputError;
using namespace vpsim::cure;
namespace pipeline = vpsim::pipeline;

constexpr double PER_MM2_TO_PER_CM2 = 100.0;  // mJ/mm^2 -> mJ/cm^2

struct CalibrateOptions {
    std::string workingCurve;
    double gelPoint = 0.0;
    bool hasGelPoint = false;
    std::string plot;
    bool json = false;
};

void printHuman(const nlohmann::json& out) {
    std::printf("Working curve %s: %d points (columns '%s', '%s')\n",
                out["working_curve"].get<std::string>().c_str(), out["n_points"].get<int>(),
                out["dose_column"].get<std::string>().c_str(),
                out["depth_column"].get<std::string>().c_str());
    std::printf("  penetration depth Dp  %.6g +- %.2g mm\n",
                out["penetration_depth_mm"].get<double>(),
                out["penetration_depth_mm_stderr"].get<double>());
    std::printf("  critical dose Ec      %.6g +- %.2g mJ/cm^2\n",
                out["critical_dose_mJ_per_cm2"].get<double>(),
                out["critical_dose_mJ_per_cm2_stderr"].get<double>());
    if (out.contains("K_cm2_per_mJ")) {
        std::printf("  FPP rate constant K   %.6g +- %.2g cm^2/mJ (gel point %.6g)\n",
                    out["K_cm2_per_mJ"].get<double>(), out["K_cm2_per_mJ_stderr"].get<double>(),
                    out["gel_point"].get<double>());
        std::printf("  attenuation mu        %.6g +- %.2g 1/mm\n",
                    out["attenuation_per_mm"].get<double>(),
                    out["attenuation_per_mm_stderr"].get<double>());
    }
    std::printf(
        "  r^2 %.6g, residual sd %.3g mm (standard errors from the least-squares covariance)\n",
        out["r_squared"].get<double>(), out["residual_std_mm"].get<double>());
    std::printf("  %6s %14s %10s %10s %10s\n", "line", "dose mJ/cm^2", "Cd mm", "fit mm",
                "resid mm");
    for (const auto& p : out["points"])
        std::printf("  %6d %14.6g %10.4f %10.4f %+10.4f\n", p["line"].get<int>(),
                    p["dose_mJ_per_cm2"].get<double>(), p["depth_mm"].get<double>(),
                    p["fitted_mm"].get<double>(), p["residual_mm"].get<double>());
    std::printf("  cure section: %s\n", out["cure_model"].dump().c_str());
}

/// Working-curve picture: Cd against ln E0 (E0 in mJ/cm^2), samples and the fitted line from Ec.
void writePlot(const std::string& path, const WorkingCurveData& data, const WorkingCurveFit& fit) {
    // The SVG chart draws polylines only: samples sorted by dose are joined, so replicates at one
    // dose appear as vertical strokes spanning their spread.
    std::vector<size_t> order(fit.count);
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return data.dose[a] != data.dose[b] ? data.dose[a] < data.dose[b]
                                            : data.cureDepth[a] < data.cureDepth[b];
    });
    vpsim::plot::Curve samples{"measured samples"};
    for (size_t i : order) {
        samples.x.push_back(std::log(data.dose[i] * PER_MM2_TO_PER_CM2));
        samples.y.push_back(data.cureDepth[i]);
    }
    const double maxDose = *std::max_element(data.dose.begin(), data.dose.end());
    vpsim::plot::Curve line{"fit Cd = Dp ln(E0/Ec)", {}, {}, vpsim::plot::paletteColour(1), true};
    for (double dose :
         {std::min(fit.criticalDose, *std::min_element(data.dose.begin(), data.dose.end())),
          maxDose}) {
        line.x.push_back(std::log(dose * PER_MM2_TO_PER_CM2));
        line.y.push_back(fit.predictDepth(dose));
    }
    char title[160];
    std::snprintf(title, sizeof title, "Working curve: Dp = %.4g mm, Ec = %.4g mJ/cm^2",
                  fit.penetrationDepth, fit.criticalDose * PER_MM2_TO_PER_CM2);
    vpsim::plot::writeLineFigure(
        vpsim::plot::figureStem(path),
        {title, "ln(E0 / (mJ/cm^2))", "cured thickness Cd (mm)", {samples, line}});
}

void runCalibrate(const CalibrateOptions& o) {
    if (o.hasGelPoint && !(o.gelPoint > 0.0 && o.gelPoint < 1.0))
        throw InputError("--gel-point must lie strictly between 0 and 1, got " +
                         vpsim::formatQuantity(o.gelPoint));
    WorkingCurveData data = loadWorkingCurveCsv(o.workingCurve);
    WorkingCurveFit fit;
    try {
        fit = fitWorkingCurve(data.dose, data.cureDepth);
    } catch (const InputError& e) {
        throw InputError(e.reason(), o.workingCurve);  // name the file for degenerate data too
    }
    nlohmann::json out =
        pipeline::calibrationJson(pipeline::makeBuiltins(), data, fit,
                                  o.hasGelPoint ? std::optional<double>(o.gelPoint) : std::nullopt);
    out["working_curve"] = o.workingCurve;
    if (!o.plot.empty()) {
        writePlot(o.plot, data, fit);
        out["plot"] = o.plot;
        vpsim::logInfo("wrote working-curve plot " + o.plot);
    }
    if (o.json)
        vpsim::cli::printJson(out);
    else
        printHuman(out);
}

vpsim::cli::CommandRegistration registerCalibrate{
    "calibrate", [](CLI::App& app, const vpsim::cli::Globals&) {
        auto* cmd = app.add_subcommand(
            "calibrate", "Fit penetration depth, critical dose and FPP K to a working curve");
        auto o = std::make_shared<CalibrateOptions>();
        cmd->add_option("--working-curve", o->workingCurve,
                        "CSV of dose and cured thickness; units in the header, e.g. "
                        "dose_mJ_per_cm2,thickness_mm")
            ->required();
        cmd->add_option("--gel-point", o->gelPoint,
                        "gel-point conversion Phi_c in (0,1); gives the FPP rate constant K");
        cmd->add_option(
            "--plot", o->plot,
            "write the working curve (samples and fit vs ln E0) to FILE.svg (and FILE.png)");
        cmd->add_flag("--json", o->json, "print JSON");
        cmd->callback([o, cmd] {
            o->hasGelPoint = cmd->count("--gel-point") > 0;
            runCalibrate(*o);
        });
    }};

}  // namespace
