#include "vpsim/report/dlp_figures.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "vpsim/core/image.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"

namespace vpsim::report {
namespace {

/// "Nice" tick spacing (1, 2 or 5 times a power of ten) giving about `count` ticks.
double tickStep(double span, int count) {
    const double raw = span / count, power = std::pow(10.0, std::floor(std::log10(raw)));
    const double f = raw / power;
    return power * (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10);
}

/// A small SVG canvas with one plot frame mapping data (x0..x1, y0..y1) to pixels.
class Canvas {
public:
    Canvas(double width, double height, const std::string& title) : mW(width), mH(height) {
        mSvg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
             << "' font-family='sans-serif' font-size='12'>\n"
             << "<rect width='100%' height='100%' fill='white'/>\n<text x='" << width / 2
             << "' y='22' text-anchor='middle' font-size='15'>" << htmlEscape(title) << "</text>\n";
    }
    void frame(double left, double top, double w, double h, double x0, double x1, double y0,
               double y1) {
        mL = left, mT = top, mPw = w, mPh = h, mX0 = x0, mX1 = x1, mY0 = y0, mY1 = y1;
    }
    double px(double x) const { return mL + (x - mX0) / (mX1 - mX0) * mPw; }
    double py(double y) const { return mT + mPh - (y - mY0) / (mY1 - mY0) * mPh; }
    /// Frame, grid, ticks and axis labels; `xTicks` false leaves the x axis to the caller.
    void axes(const std::string& xLabel, const std::string& yLabel, bool xTicks = true,
              bool grid = true) {
        mSvg << "<rect x='" << mL << "' y='" << mT << "' width='" << mPw << "' height='" << mPh
             << "' fill='none' stroke='black'/>\n";
        if (xTicks) {
            const double s = tickStep(mX1 - mX0, 6);
            for (double t = std::ceil(mX0 / s) * s; t <= mX1 + 1e-9 * s; t += s)
                mSvg << "<line x1='" << px(t) << "' y1='" << mT + mPh << "' x2='" << px(t)
                     << "' y2='" << mT + mPh + 4 << "' stroke='black'/><text x='" << px(t)
                     << "' y='" << mT + mPh + 17 << "' text-anchor='middle'>"
                     << formatNumber(std::abs(t) < 1e-9 * s ? 0.0 : t, 4) << "</text>\n";
        }
        const double s = tickStep(mY1 - mY0, 6);
        for (double t = std::ceil(mY0 / s) * s; t <= mY1 + 1e-9 * s; t += s)
            mSvg << "<line x1='" << mL << "' y1='" << py(t) << "' x2='" << mL + mPw << "' y2='"
                 << py(t) << "' stroke='" << (grid ? "#e4e4e4" : "none") << "'/><text x='" << mL - 6
                 << "' y='" << py(t) + 4 << "' text-anchor='end'>"
                 << formatNumber(std::abs(t) < 1e-9 * s ? 0.0 : t, 4) << "</text>\n";
        mSvg << "<text x='" << mL + mPw / 2 << "' y='" << mT + mPh + 36 << "' text-anchor='middle'>"
             << htmlEscape(xLabel) << "</text>\n<text transform='"
             << "translate(" << mL - 48 << "," << mT + mPh / 2
             << ") rotate(-90)' text-anchor='middle'>" << htmlEscape(yLabel) << "</text>\n";
    }
    void rect(double x, double y, double w, double h, const std::string& fill) {
        mSvg << "<rect x='" << x << "' y='" << y << "' width='" << w << "' height='" << h
             << "' fill='" << fill << "'/>\n";
    }
    void line(double x0, double y0, double x1, double y1, const std::string& colour) {
        mSvg << "<line x1='" << x0 << "' y1='" << y0 << "' x2='" << x1 << "' y2='" << y1
             << "' stroke='" << colour << "' stroke-width='1.5'/>\n";
    }
    void text(double x, double y, const std::string& t, const char* anchor = "start") {
        mSvg << "<text x='" << x << "' y='" << y << "' text-anchor='" << anchor << "'>"
             << htmlEscape(t) << "</text>\n";
    }
    void write(const std::string& path) {
        mSvg << "</svg>\n";
        writeFileAtomic(path, mSvg.str());
    }

private:
    std::ostringstream mSvg;
    double mW, mH, mL = 0, mT = 0, mPw = 1, mPh = 1, mX0 = 0, mX1 = 1, mY0 = 0, mY1 = 1;
};

std::string greyColour(int g) {
    std::ostringstream c;
    c << "rgb(" << g << ',' << g << ',' << g << ')';
    return c.str();
}

void writeFeatures(const std::string& path, const validate::FeatureMeasurements& f,
                   const std::vector<double>& uniform) {
    const char* colours[] = {"#999999", "#d62728", "#1f77b4", "#2ca02c"};
    const char* labels[] = {"objective", "uniform plan (simulated)", "this plan (simulated)",
                            "measured (mean, range)"};
    double top = 0.0;
    for (size_t i = 0; i < f.probes.size(); ++i) {
        top = std::max({top, f.probes[i].objective, f.simulated[i]});
        for (double m : f.probes[i].measured) top = std::max(top, m);
        const double u = i < uniform.size() ? uniform[i] : NAN;
        if (std::isfinite(u)) top = std::max(top, u);
    }
    Canvas c(720, 420, "Features: predicted vs objective vs measured (seed 001 Table 2)");
    c.frame(80, 40, 420, 310, 0, double(f.probes.size()), 0, top * 1.1 + 1e-9);
    c.axes("", "length (mm)", false);
    for (size_t i = 0; i < f.probes.size(); ++i) {
        const validate::FeatureProbe& p = f.probes[i];
        double mean = 0, lo = INFINITY, hi = -INFINITY;
        for (double m : p.measured)
            mean += m / double(p.measured.size()), lo = std::min(lo, m), hi = std::max(hi, m);
        const double values[] = {p.objective, i < uniform.size() ? uniform[i] : NAN, f.simulated[i],
                                 p.measured.empty() ? NAN : mean};
        for (int b = 0; b < 4; ++b) {
            if (!std::isfinite(values[b])) continue;
            const double x0 = c.px(double(i) + 0.1 + 0.2 * b),
                         x1 = c.px(double(i) + 0.28 + 0.2 * b);
            c.rect(x0, c.py(values[b]), x1 - x0, c.py(0) - c.py(values[b]), colours[b]);
            if (b == 3 && p.measured.size() > 1)
                c.line(0.5 * (x0 + x1), c.py(lo), 0.5 * (x0 + x1), c.py(hi), "black");
        }
        c.text(c.px(double(i) + 0.5), c.py(0) + 17, p.name, "middle");
    }
    for (int b = 0; b < 4; ++b) {
        c.rect(515, 50 + 20 * b, 14, 12, colours[b]);
        c.text(535, 61 + 20 * b, labels[b]);
    }
    c.write(path);
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
    PlotSeries s{"part (solid = top)", z, {}, "#bbbbbb", true};
    for (bool v : solid) s.y.push_back(v ? top : 0.0);
    writeSvgLinePlot(
        outDir + "/dlp_dose_along_z.svg", "Dose per layer along Z" + where,
        "z, height of the layer's top (mm)", "dose (mJ/cm^2)",
        {s, {"optimised dose", z, dose, "#1f77b4"}, {"quantised dose", z, qdose, "#d62728", true}});
    PlotSeries part{"part (solid = 1)", z, {}, "#bbbbbb", true};
    for (bool v : solid) part.y.push_back(v ? 1.0 : 0.0);
    const double gel = column["gel_point"], target = column["target_conversion"];
    writeSvgLinePlot(
        outDir + "/dlp_conversion_along_z.svg", "Conversion along Z after quantisation" + where,
        "z (mm)", "conversion Phi (-)",
        {part,
         {"conversion", z, conversion, "#1f77b4"},
         {"gel point Phi_c", {z.front(), z.back()}, {gel, gel}, "#d62728", true},
         {"target Phi_obj", {z.front(), z.back()}, {target, target}, "#2ca02c", true}});
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

void writeMask(const std::string& path, const plan::ScanPlan& plan, long layer,
               const std::vector<double>& greyDose) {
    if (layer < 0 || size_t(layer) >= plan.layers.size() || plan.layers[layer].masks.empty())
        return;
    const plan::MaskImage& m = plan.layers[size_t(layer)].masks[0];
    const std::vector<int> grey = greyOf(m, greyDose);
    const double x0 = m.originX, x1 = m.originX + m.width * m.pixelPitch, y0 = m.originY,
                 y1 = m.originY + m.height * m.pixelPitch;
    const double plotW = 480, plotH = std::clamp(plotW * (y1 - y0) / (x1 - x0), 120.0, 480.0);
    Canvas c(800, plotH + 110,
             "Mask of layer " + std::to_string(layer) +
                 " (z = " + formatNumber(plan.layers[size_t(layer)].z, 4) + " mm)");
    c.frame(80, 40, plotW, plotH, x0, x1, y0, y1);
    // Pixels as runs of equal grey per row (row 0 at y0, drawn at the bottom).
    for (int j = 0; j < m.height; ++j)
        for (int i = 0; i < m.width;) {
            int e = i;
            while (e < m.width && grey[size_t(j) * m.width + e] == grey[size_t(j) * m.width + i])
                ++e;
            const double xa = c.px(x0 + i * m.pixelPitch), xb = c.px(x0 + e * m.pixelPitch);
            const double ya = c.py(y0 + (j + 1) * m.pixelPitch), yb = c.py(y0 + j * m.pixelPitch);
            c.rect(xa, ya, xb - xa + 0.3, yb - ya + 0.3, greyColour(grey[size_t(j) * m.width + i]));
            i = e;
        }
    c.axes("x (mm)", "y (mm)", true, false);
    // Grey scale with each level's dose.
    const double bx = 80 + plotW + 30, bh = plotH;
    for (int g = 0; g < 256; ++g)
        c.rect(bx, 40 + bh * (1.0 - (g + 1) / 256.0), 18, bh / 256.0 + 0.5, greyColour(g));
    for (int g : {0, 150, 175, 200, 225, 255})
        c.text(
            bx + 24, 44 + bh * (1.0 - (g + 0.5) / 256.0),
            "grey " + std::to_string(g) + ": " + formatNumber(greyDose[size_t(g)], 3) + " mJ/cm^2");
    c.write(path);
}

void writeHistogram(const std::string& path, const std::vector<double>& counts) {
    double top = 1.0;
    for (double v : counts) top = std::max(top, v);
    Canvas c(720, 420, "Grey levels of the exposed pixels (all layers)");
    c.frame(80, 40, 580, 310, 0, 256, 0, std::ceil(std::log10(top)) + 0.2);
    for (int g = 0; g < 256; ++g)
        if (counts[size_t(g)] > 0) {
            const double h = std::log10(counts[size_t(g)]) + 0.2;  // 1 pixel shows as a stub
            c.rect(c.px(g), c.py(h), std::max(c.px(g + 1) - c.px(g), 1.0), c.py(0) - c.py(h),
                   "#1f77b4");
        }
    c.axes("grey level (0-255)", "log10(pixel-layers)");
    c.write(path);
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
