#include "vpsim/report/dlp_figures.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/plot/plot.h"

namespace vpsim::report {
namespace {

void writeFeatures(const std::string& path, const validate::FeatureMeasurements& f,
                   const std::vector<double>& uniform) {
    const plot::Rgb colours[] = {{153, 153, 153}, {214, 39, 40}, {31, 119, 180}, {44, 160, 44}};
    const char* labels[] = {"objective", "uniform plan (simulated)", "this plan (simulated)",
                            "measured (mean, range)"};
    plot::LineFigure figure;
    figure.title = "Features: predicted vs objective vs measured (seed 001 Table 2)";
    figure.yLabel = "length (mm)";
    for (int b = 0; b < 4; ++b) {
        plot::Curve bars{labels[b], {}, {}, colours[b]};
        bars.style = plot::CurveStyle::Bars;
        bars.barWidth = 0.18;
        figure.curves.push_back(bars);
    }
    plot::Curve& measured = figure.curves[3];
    for (size_t i = 0; i < f.probes.size(); ++i) {
        const validate::FeatureProbe& p = f.probes[i];
        double mean = 0, lo = INFINITY, hi = -INFINITY;
        for (double m : p.measured)
            mean += m / double(p.measured.size()), lo = std::min(lo, m), hi = std::max(hi, m);
        const double values[] = {p.objective, i < uniform.size() ? uniform[i] : NAN, f.simulated[i],
                                 p.measured.empty() ? NAN : mean};
        for (int b = 0; b < 4; ++b) {
            if (!std::isfinite(values[b])) continue;
            figure.curves[b].x.push_back(double(i) + 0.2 * (b - 1.5));
            figure.curves[b].y.push_back(values[b]);
        }
        if (!p.measured.empty())
            measured.errorLow.push_back(p.measured.size() > 1 ? lo : NAN),
                measured.errorHigh.push_back(p.measured.size() > 1 ? hi : NAN);
        figure.xCategories.push_back({double(i), p.name});
    }
    plot::writeLineFigure(plot::figureStem(path), figure);
}

void writeAlongZ(const std::string& outDir, const nlohmann::json& column) {
    const std::vector<double> z = column["z_mm"], dose = column["dose_mJ_per_cm2"],
                              qdose = column["quantised_dose_mJ_per_cm2"],
                              conversion = column["conversion"];
    const std::vector<bool> solid = column["solid"];
    const double xMm = column["x_mm"], yMm = column["y_mm"];
    const std::string where =
        " at x = " + formatNumber(xMm, 4) + " mm, y = " + formatNumber(yMm, 4) + " mm";
    double top = 0.0;
    for (double d : qdose) top = std::max(top, d);
    const plot::Rgb grey{187, 187, 187}, blue{31, 119, 180}, red{214, 39, 40}, green{44, 160, 44};
    plot::Curve part{"part (solid = top)", z, {}, grey, true};
    for (bool v : solid) part.y.push_back(v ? top : 0.0);
    plot::writeLineFigure(
        outDir + "/dlp_dose_along_z",
        {"Dose per layer along Z" + where,
         "z, height of the layer's top (mm)",
         "dose (mJ/cm#u2#d)",
         {part, {"optimised dose", z, dose, blue}, {"quantised dose", z, qdose, red, true}}});
    part.label = "part (solid = 1)";
    part.y.clear();
    for (bool v : solid) part.y.push_back(v ? 1.0 : 0.0);
    const double gel = column["gel_point"], target = column["target_conversion"];
    plot::writeLineFigure(
        outDir + "/dlp_conversion_along_z",
        {"Conversion along Z after quantisation" + where,
         "z (mm)",
         "conversion Phi (-)",
         {part,
          {"conversion", z, conversion, blue},
          {"gel point Phi_c", {z.front(), z.back()}, {gel, gel}, red, true},
          {"target Phi_obj", {z.front(), z.back()}, {target, target}, green, true}}});
}

/// Grey level of each pixel: the level whose dose is nearest (the masks hold quantised doses).
std::vector<int> greyOf(const plan::MaskImage& m, const std::vector<double>& greyDose) {
    std::vector<int> grey(m.dose.size(), 0);
    for (size_t i = 0; i < grey.size(); ++i) {
        const double d = 100.0 * m.dose[i];
        if (!(d > 0.0)) continue;
        double best = INFINITY;
        for (int g = 0; g < 256; ++g)
            if (std::abs(greyDose[size_t(g)] - d) < best)
                best = std::abs(greyDose[size_t(g)] - d), grey[i] = g;
    }
    return grey;
}

/// One layer's mask as projected: grey levels drawn as their doses (mJ/cm^2) on a grey scale.
void writeMask(const std::string& path, const plan::ScanPlan& plan, long layer,
               const std::vector<double>& greyDose) {
    if (layer < 0 || size_t(layer) >= plan.layers.size() || plan.layers[layer].masks.empty())
        return;
    const plan::MaskImage& m = plan.layers[size_t(layer)].masks[0];
    const std::vector<int> grey = greyOf(m, greyDose);
    plot::MapFigure f;
    f.title = "Mask of layer " + std::to_string(layer) +
              " (z = " + formatNumber(plan.layers[size_t(layer)].z, 4) + " mm)";
    f.nx = m.width, f.ny = m.height;
    f.x0 = m.originX, f.x1 = m.originX + m.width * m.pixelPitch;
    f.y0 = m.originY, f.y1 = m.originY + m.height * m.pixelPitch;
    for (int g : grey) f.values.push_back(float(greyDose[size_t(g)]));  // row 0 at y0
    f.scale = {plot::ColourMap::Grey,
               0.0,
               greyDose[255],
               "dose of the grey level (mJ/cm#u2#d)",
               false,
               false};
    f.note = "grey levels: ";
    for (int g : {150, 200, 255})
        f.note += std::to_string(g) + " = " + formatNumber(greyDose[size_t(g)], 3) +
                  (g < 255 ? " mJ/cm#u2#d, " : " mJ/cm#u2#d");
    plot::writeMapFigure(plot::figureStem(path), f);
}

void writeHistogram(const std::string& path, const std::vector<double>& counts) {
    plot::Curve bars{"", {}, {}, {31, 119, 180}};
    bars.style = plot::CurveStyle::Bars;
    bars.barWidth = 1.0;
    for (int g = 0; g < 256; ++g)
        if (counts[size_t(g)] > 0) bars.x.push_back(g), bars.y.push_back(counts[size_t(g)]);
    plot::LineFigure figure{"Grey levels of the exposed pixels (all layers)",
                            "grey level (0-255)",
                            "pixel-layers",
                            {bars}};
    figure.logY = true;
    plot::writeLineFigure(plot::figureStem(path), figure);
}

}  // namespace

void writeDlpFigures(const std::string& outDir, const DlpFigureInputs& in) {
    const nlohmann::json& data = in.data;
    if (!data.is_object() || !data.contains("column")) return;
    writeFileAtomic(outDir + "/dlp_figures.json", data.dump(1));
    if (!in.features.probes.empty())
        writeFeatures(outDir + "/dlp_features.svg", in.features, in.uniformFeatures);
    writeAlongZ(outDir, data["column"]);
    const std::vector<double> greyDose = data["grey_dose_mJ_per_cm2"];
    writeMask(outDir + "/dlp_mask.svg", in.plan, data.value("layer", 0L), greyDose);
    if (!in.greyHistogram.empty())
        writeHistogram(outDir + "/dlp_grey_histogram.svg", in.greyHistogram);
}

}  // namespace vpsim::report
