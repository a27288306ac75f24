#include "vpsim/plot/plot.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "plplot_page.h"
#include "vpsim/core/error.h"

namespace vpsim::plot {

void useColour(PLINT index, Rgb c) {
    plscol0(index, c.r, c.g, c.b);
    plcol0(index);
}

void polyline(const std::vector<double>& x, const std::vector<double>& y) {
    std::vector<PLFLT> px, py;
    auto flush = [&] {
        if (px.size() > 1) plline(PLINT(px.size()), px.data(), py.data());
        px.clear(), py.clear();
    };
    for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
        if (std::isfinite(x[i]) && std::isfinite(y[i]))
            px.push_back(x[i]), py.push_back(y[i]);
        else
            flush();
    }
    flush();
}

void legend(const std::vector<LegendEntry>& entries, PLINT position, double x, double y,
            int columns) {
    const PLINT n = PLINT(entries.size());
    if (n == 0) return;
    std::vector<PLINT> opts, textColours(n, BLACK), colours, styles, zeros(n, 0);
    std::vector<PLFLT> widths(n, 2.0), ones(n, 1.0);
    std::vector<const char*> text, symbols(n, "");
    for (const LegendEntry& e : entries) {
        opts.push_back(e.box ? PL_LEGEND_COLOR_BOX : PL_LEGEND_LINE);
        text.push_back(e.label.c_str());
        colours.push_back(e.colour);
        styles.push_back(e.lineStyle);
    }
    PLFLT w = 0, h = 0;
    pllegend(&w, &h, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX, position, x, y, 0.07, WHITE,
             BLACK, 1, (n + columns - 1) / columns, columns, n, opts.data(), 0.8, 0.8, 2.0, 0.0,
             textColours.data(), text.data(), colours.data(), zeros.data(), ones.data(),
             widths.data(), colours.data(), styles.data(), widths.data(), zeros.data(), ones.data(),
             zeros.data(), symbols.data());
}

void drawCurve(const Curve& c, double base) {
    pllsty(c.dashed ? 2 : 1);
    plwidth(1.6);
    if (c.style == CurveStyle::Bars) {
        for (size_t i = 0; i < std::min(c.x.size(), c.y.size()); ++i) {
            if (!std::isfinite(c.x[i]) || !std::isfinite(c.y[i])) continue;
            const double a = c.x[i] - c.barWidth / 2, b = c.x[i] + c.barWidth / 2;
            PLFLT bx[] = {a, b, b, a}, by[] = {base, base, c.y[i], c.y[i]};
            plfill(4, bx, by);
        }
    } else {
        polyline(c.x, c.y);
    }
    if (c.errorLow.size() == c.x.size() && c.errorHigh.size() == c.x.size()) {
        plcol0(BLACK);
        pllsty(1);
        for (size_t i = 0; i < c.x.size(); ++i)
            if (std::isfinite(c.errorLow[i]) && std::isfinite(c.errorHigh[i])) {
                PLFLT x = c.x[i], lo = c.errorLow[i], hi = c.errorHigh[i];
                plerry(1, &x, &lo, &hi);
            }
    }
    pllsty(1);
    plwidth(1);
}

double niceStep(double span, int parts) {
    if (!(span > 0) || parts < 1) return 1;
    const double raw = span / parts, power = std::pow(10.0, std::floor(std::log10(raw)));
    const double f = raw / power;
    return power * (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10);
}

std::string figureStem(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))  // FILE would become FILE.svg inside nothing
        throw InputError("cannot write output: is a directory (give a file name)", path);
    const bool svg = path.size() > 4 && path.compare(path.size() - 4, 4, ".svg") == 0;
    return svg ? path.substr(0, path.size() - 4) : path;
}

Rgb paletteColour(size_t k) {
    static const Rgb palette[] = {{31, 119, 180},  {214, 39, 40}, {44, 160, 44}, {255, 127, 14},
                                  {148, 103, 189}, {140, 86, 75}, {23, 190, 207}};
    return palette[k % 7];
}

namespace {

struct Range {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    void include(double v) {
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
    void settle() {
        if (!(lo <= hi)) lo = 0, hi = 1;
        if (hi - lo < 1e-12) lo -= 0.5, hi += 0.5;
    }
};

}  // namespace

namespace {

/// `figure` with its y values (and error bars) as log10, non-positive ones as NaN.
LineFigure logarithmic(LineFigure figure) {
    auto toLog = [](std::vector<double>& values) {
        for (double& v : values) v = v > 0 ? std::log10(v) : NAN;
    };
    for (Curve& c : figure.curves) toLog(c.y), toLog(c.errorLow), toLog(c.errorHigh);
    return figure;
}

}  // namespace

void writeLineFigure(const std::string& stem, const LineFigure& figure) {
    const LineFigure f = figure.logY ? logarithmic(figure) : figure;
    Range x, y;
    bool bars = false;
    for (const Curve& c : f.curves) {
        const double half = c.style == CurveStyle::Bars ? c.barWidth / 2 : 0;
        bars = bars || c.style == CurveStyle::Bars;
        for (size_t i = 0; i < std::min(c.x.size(), c.y.size()); ++i)
            if (std::isfinite(c.x[i]) && std::isfinite(c.y[i]))
                x.include(c.x[i] - half), x.include(c.x[i] + half), y.include(c.y[i]);
        for (double v : c.errorLow) y.include(v);
        for (double v : c.errorHigh) y.include(v);
    }
    for (const auto& [at, label] : f.xCategories) x.include(at - 0.5), x.include(at + 0.5);
    if (bars && !f.logY) y.include(0);
    x.settle(), y.settle();
    const double pad = 0.05 * (y.hi - y.lo);
    // From 0 when the values are positive and near it, except on a log axis (where a bar of 1
    // would have no height).
    y.lo = !f.logY && y.lo >= 0 && y.lo - pad < 0 ? 0 : y.lo - pad, y.hi += pad;
    if (f.equalAspect) {  // a margin all round, the same in x and y
        const double m = 0.03 * std::max(x.hi - x.lo, y.hi - y.lo);
        x.lo -= m, x.hi += m, y.lo = y.lo + pad - m, y.hi = y.hi - pad + m;
    }
    // Plot area in pixels: 640 x 320, or at the data's aspect within 640 x 560.
    double pw = 640, ph = 320;
    if (f.equalAspect) {
        const double aspect = (y.hi - y.lo) / (x.hi - x.lo);
        ph = pw * aspect;
        if (ph > 560) ph = 560, pw = ph / aspect;
    }
    size_t labelled = 0, longest = 0;
    for (const Curve& c : f.curves)
        labelled += !c.label.empty(), longest = std::max(longest, drawnLength(c.label));
    const bool legendBelow = f.equalAspect && f.legend && labelled > 0;
    const int columns = legendColumns(labelled, longest, pw);
    const size_t legendRows = (labelled + columns - 1) / columns;
    const double left = 95, right = 30, top = 45;
    const double bottom =
        65 + (f.note.empty() ? 0 : 25) + (legendBelow ? 14 + 25.0 * double(legendRows) : 0);
    const int width = int(left + std::max(pw, 300.0) + right), height = int(top + ph + bottom);
    plotTwice(stem, width, height, [&](bool) {
        plvpor(left / width, (left + pw) / width, bottom / height, (bottom + ph) / height);
        plwind(x.lo, x.hi, y.lo, y.hi);
        const char* xBox = f.xCategories.empty() ? "bcnst" : "bc";
        plcol0(LIGHT);
        plbox(f.xCategories.empty() ? "g" : "", 0, 0, f.logY ? "gl" : "g", 0, 0);
        std::vector<LegendEntry> entries;
        PLINT index = FIRST_FREE;
        for (const Curve& c : f.curves) {
            useColour(index, c.colour);
            drawCurve(c, f.logY ? y.lo : 0.0);
            if (!c.label.empty())
                entries.push_back({c.label, index, c.dashed ? 2 : 1, c.style == CurveStyle::Bars});
            ++index;
        }
        plcol0(BLACK);
        plbox(xBox, 0, 0, f.logY ? "bcnstvl" : "bcnstv", 0, 0);
        for (const auto& [at, label] : f.xCategories)
            plmtex("b", 1.6, (at - x.lo) / (x.hi - x.lo), 0.5, label.c_str());
        plmtex("t", 1.5, 0.5, 0.5, f.title.c_str());
        plmtex("b", 3.2, 0.5, 0.5, f.xLabel.c_str());
        plmtex("l", 5.0, 0.5, 0.5, f.yLabel.c_str());
        if (!f.note.empty())
            plmtex("b", 5.0 + (legendBelow ? 1.6 * double(legendRows) + 0.8 : 0.0), 0.0, 0.0,
                   f.note.c_str());
        if (!f.legend || entries.empty()) return;
        if (legendBelow)
            legend(entries, PL_POSITION_BOTTOM | PL_POSITION_OUTSIDE | PL_POSITION_VIEWPORT, 0.0,
                   55.0 / ph, columns);
        else
            legend(entries, PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE, 0.02, 0.02,
                   1);
    });
}

}  // namespace vpsim::plot
