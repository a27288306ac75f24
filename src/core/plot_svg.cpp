#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "vpsim/core/image.h"
#include "vpsim/core/io.h"

namespace vpsim {
namespace {

constexpr double WIDTH = 720, HEIGHT = 480, LEFT = 80, RIGHT = 170, TOP = 40, BOTTOM = 60;
const char* PALETTE[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                         "#9467bd", "#8c564b", "#17becf"};

std::string escapeXml(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else
            out += c;
    }
    return out;
}

/// "Nice" tick spacing (1, 2 or 5 times a power of ten) giving about `count` ticks.
double tickStep(double span, int count) {
    double raw = span / count;
    double power = std::pow(10.0, std::floor(std::log10(raw)));
    double fraction = raw / power;
    return power * (fraction < 1.5 ? 1 : fraction < 3.5 ? 2 : fraction < 7.5 ? 5 : 10);
}

struct Range {
    double lo = std::numeric_limits<double>::infinity(),
           hi = -std::numeric_limits<double>::infinity();
    void include(double v) {
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
    void settle() {
        if (!(lo <= hi)) lo = 0, hi = 1;
        if (hi - lo < 1e-300) lo -= 0.5, hi += 0.5;
    }
};

}  // namespace

void writeSvgLinePlot(const std::string& path, const std::string& title, const std::string& xLabel,
                      const std::string& yLabel, const std::vector<PlotSeries>& series) {
    Range xr, yr;
    for (const auto& s : series)
        for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
            xr.include(s.x[i]), yr.include(s.y[i]);
    xr.settle();
    yr.settle();
    const double plotW = WIDTH - LEFT - RIGHT, plotH = HEIGHT - TOP - BOTTOM;
    auto px = [&](double x) { return LEFT + (x - xr.lo) / (xr.hi - xr.lo) * plotW; };
    auto py = [&](double y) { return TOP + plotH - (y - yr.lo) / (yr.hi - yr.lo) * plotH; };

    std::ostringstream svg;
    svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << WIDTH << "' height='" << HEIGHT
        << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' "
           "fill='white'/>\n";
    svg << "<text x='" << WIDTH / 2 << "' y='22' text-anchor='middle' font-size='15'>"
        << escapeXml(title) << "</text>\n";
    svg << "<rect x='" << LEFT << "' y='" << TOP << "' width='" << plotW << "' height='" << plotH
        << "' fill='none' stroke='black'/>\n";
    double xs = tickStep(xr.hi - xr.lo, 6), ys = tickStep(yr.hi - yr.lo, 6);
    for (double t = std::ceil(xr.lo / xs) * xs; t <= xr.hi + 1e-9 * xs; t += xs)
        svg << "<line x1='" << px(t) << "' y1='" << TOP + plotH << "' x2='" << px(t) << "' y2='"
            << TOP << "' stroke='#ddd'/><text x='" << px(t) << "' y='" << TOP + plotH + 16
            << "' text-anchor='middle'>" << (std::abs(t) < 1e-12 * xs ? 0.0 : t) << "</text>\n";
    for (double t = std::ceil(yr.lo / ys) * ys; t <= yr.hi + 1e-9 * ys; t += ys)
        svg << "<line x1='" << LEFT << "' y1='" << py(t) << "' x2='" << LEFT + plotW << "' y2='"
            << py(t) << "' stroke='#ddd'/><text x='" << LEFT - 6 << "' y='" << py(t) + 4
            << "' text-anchor='end'>" << (std::abs(t) < 1e-12 * ys ? 0.0 : t) << "</text>\n";
    svg << "<text x='" << LEFT + plotW / 2 << "' y='" << HEIGHT - 15 << "' text-anchor='middle'>"
        << escapeXml(xLabel) << "</text>\n";
    svg << "<text transform='translate(18," << TOP + plotH / 2
        << ") rotate(-90)' text-anchor='middle'>" << escapeXml(yLabel) << "</text>\n";
    for (size_t k = 0; k < series.size(); ++k) {
        const auto& s = series[k];
        std::string colour = s.colour.empty() ? PALETTE[k % 7] : s.colour;
        // A non-finite point breaks the line (separate segments in one series).
        const std::string open = "<polyline fill='none' stroke='" + colour +
                                 "' stroke-width='1.8'" +
                                 (s.dashed ? " stroke-dasharray='6,4'" : "") + " points='";
        svg << open;
        for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]))
                svg << px(s.x[i]) << ',' << py(s.y[i]) << ' ';
            else
                svg << "'/>\n" << open;
        }
        svg << "'/>\n";
        double ly = TOP + 14 + 18 * double(k);
        svg << "<line x1='" << WIDTH - RIGHT + 10 << "' y1='" << ly << "' x2='"
            << WIDTH - RIGHT + 34 << "' y2='" << ly << "' stroke='" << colour
            << "' stroke-width='2'" << (s.dashed ? " stroke-dasharray='6,4'" : "") << "/><text x='"
            << WIDTH - RIGHT + 40 << "' y='" << ly + 4 << "'>" << escapeXml(s.label) << "</text>\n";
    }
    svg << "</svg>\n";
    writeFileAtomic(path, svg.str());
}

}  // namespace vpsim
