// Pictures of a beam kernel, after seed 000 Fig. 11 (intensity contours with and without
// scattering), Fig. 12 (amplitude and Gaussian radius against depth) and Fig. 13 (the Eq. 12 fit):
// heat maps (PNG) and vector pictures with axes in um (SVG: contours_scattering.svg,
// contours_fit.svg, amplitude_vs_depth.svg, radius_vs_depth.svg).

#include <algorithm>
#include <cmath>
#include <functional>

#include "vpsim/core/image.h"
#include "vpsim/core/io.h"
#include "vpsim/kernel/beam_kernel.h"

namespace vpsim::kernel {

namespace {

constexpr double UM = 1000.0;
constexpr int TARGET_WIDTH = 600;  // pixels across the mirrored r range

/// Heat map of field(r, z): r from -rMax to rMax left to right, z from 0 at the top down.
void writeField(const std::string& path, const BeamKernel& k,
                const std::function<double(double, double)>& field, double hi,
                const std::vector<double>& contours) {
    const double rMax = k.rBin * k.rBins, zMax = k.zBin * k.zBins;
    const double pixel = 2 * rMax / TARGET_WIDTH;
    const int width = TARGET_WIDTH, height = std::max(1, int(std::lround(zMax / pixel)));
    std::vector<float> values(size_t(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            values[size_t(y) * width + x] =
                float(field(std::abs(-rMax + (x + 0.5) * pixel), (y + 0.5) * pixel));
    writePng(path, heatMap(values, width, height, 0.0, hi, contours));
}

/// Outermost radius where field(r, z) >= level, interpolated inside the crossing step; -1 when
/// the field is below the level at every r.
double levelRadius(const std::function<double(double, double)>& field, double z, double level,
                   double rMax, double step) {
    double radius = -1;
    for (double r = 0; r <= rMax; r += step) {
        double v = field(r, z);
        if (v < level) continue;
        double next = field(r + step, z);
        radius = next < level ? r + step * (v - level) / std::max(v - next, 1e-300) : r + step;
    }
    return std::min(radius, rMax);
}

/// One iso-intensity contour in the (r, z) plane, mirrored about the axis: down the left side
/// (-r, z) and back up the right (+r, z); depths plotted as -z so that the surface is on top.
PlotSeries contourSeries(const BeamKernel& k, const std::function<double(double, double)>& field,
                         double level, const std::string& label, const std::string& colour,
                         bool dashed) {
    PlotSeries series{label, {}, {}, colour, dashed};
    const double rMax = k.rBin * k.rBins, zMax = k.zBin * k.zBins, dz = k.zBin / 2;
    std::vector<std::pair<double, double>> side;  // (r, z)
    for (double z = 0; z <= zMax; z += dz) {
        double r = levelRadius(field, z, level, rMax, k.rBin / 4);
        if (r < 0) {
            if (!side.empty()) break;  // below the contour's bottom
            continue;
        }
        side.push_back({r, z});
    }
    for (const auto& [r, z] : side) {
        series.x.push_back(-r * UM);
        series.y.push_back(-z * UM);
    }
    for (auto it = side.rbegin(); it != side.rend(); ++it) {
        series.x.push_back(it->first * UM);
        series.y.push_back(-it->second * UM);
    }
    return series;
}

/// Seed 000 Fig. 11 / 13 as vector pictures: contours of `a` (solid) and `b` (dashed) at the
/// same absolute levels.
void writeContours(const std::string& path, const std::string& title, const BeamKernel& k,
                   const std::function<double(double, double)>& a, const std::string& aName,
                   const std::function<double(double, double)>& b, const std::string& bName,
                   const std::vector<double>& fractions, double reference) {
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd"};
    std::vector<PlotSeries> series;
    for (size_t i = 0; i < fractions.size(); ++i) {
        const std::string pct = std::to_string(int(std::lround(fractions[i] * 100))) + "%";
        series.push_back(contourSeries(k, a, fractions[i] * reference, aName + " " + pct,
                                       colours[i % 5], false));
        series.push_back(
            contourSeries(k, b, fractions[i] * reference, bName + " " + pct, colours[i % 5], true));
    }
    writeSvgLinePlot(path, title, "r (um)", "-z, depth below the surface (um)", series);
}

}  // namespace

void writeKernelFigures(const std::string& directory, const BeamKernel& k) {
    createDirectories(directory);
    const double peakNoScatter = k.beerLambert(0, 0);
    const double peakTable = *std::max_element(k.intensity.begin(), k.intensity.end());
    const double hi = std::max(peakNoScatter, peakTable);
    // The same absolute iso-intensity levels in every picture, so the contours compare directly.
    std::vector<double> contours;
    for (double f : {0.05, 0.1, 0.2, 0.4, 0.8}) contours.push_back(f * peakNoScatter);
    writeField(
        directory + "/intensity_scattered.png", k,
        [&k](double r, double z) { return k.sample(r, z); }, hi, contours);
    writeField(
        directory + "/intensity_no_scattering.png", k,
        [&k](double r, double z) { return k.beerLambert(r, z); }, hi, contours);
    writeField(
        directory + "/intensity_fit.png", k, [&k](double r, double z) { return k.fitted(r, z); },
        hi, contours);

    // The same levels as vector contours, in % of the unscattered peak 2P(1-Rsp)/(pi W0^2).
    const std::vector<double> fractions = {0.1, 0.2, 0.4, 0.8};
    auto table = [&k](double r, double z) { return k.sample(r, z); };
    writeContours(
        directory + "/contours_scattering.svg",
        "Iso-intensity contours with and without scattering (Fig. 11), % of I0", k, table, "MC",
        [&k](double r, double z) { return k.beerLambert(r, z); }, "no scatt.", fractions,
        peakNoScatter);
    writeContours(
        directory + "/contours_fit.svg",
        "Monte Carlo table against the Eq. 12 fit (Fig. 13), % of I0", k, table, "MC",
        [&k](double r, double z) { return k.fitted(r, z); }, "Eq. 12", fractions, peakNoScatter);

    PlotSeries mcAmplitude{"Monte Carlo Ie(0,z)", {}, {}}, mcRadius{"Monte Carlo We(z)", {}, {}};
    PlotSeries blAmplitude{"no scattering (Beer-Lambert)", {}, {}},
        blRadius{"no scattering W0", {}, {}};
    PlotSeries fitAmplitude{"Eq. 12 fit", {}, {}}, fitRadius{"Eq. 12 We3D", {}, {}};
    fitAmplitude.dashed = fitRadius.dashed = true;
    for (uint32_t iz = 0; iz < k.zBins; ++iz) {
        double z = (iz + 0.5) * k.zBin;
        if (k.depthAmplitude[iz] > 0) {
            mcAmplitude.x.push_back(z * UM);
            mcAmplitude.y.push_back(k.depthAmplitude[iz]);
            mcRadius.x.push_back(z * UM);
            mcRadius.y.push_back(k.depthRadius[iz] * UM);
        }
        blAmplitude.x.push_back(z * UM);
        blAmplitude.y.push_back(k.beerLambert(0, z));
        blRadius.x.push_back(z * UM);
        blRadius.y.push_back(k.w0 * UM);
        fitAmplitude.x.push_back(z * UM);
        fitAmplitude.y.push_back(k.fitted(0, z));
        fitRadius.x.push_back(z * UM);
        fitRadius.y.push_back(k.fit.we3d * UM);
    }
    double top = 0;
    for (double a : k.depthAmplitude) top = std::max(top, a);
    PlotSeries zmaxLine{"zmax", {k.zmax * UM, k.zmax * UM}, {0.0, top}, "#555555", true};
    writeSvgLinePlot(directory + "/amplitude_vs_depth.svg",
                     "Beam amplitude Ie(0, z) against depth (Fig. 12)", "depth z (um)",
                     "Ie(0, z) (mW/mm^2)", {mcAmplitude, blAmplitude, fitAmplitude, zmaxLine});
    writeSvgLinePlot(directory + "/radius_vs_depth.svg",
                     "Gaussian radius We(z) against depth (Fig. 12)", "depth z (um)", "We (um)",
                     {mcRadius, blRadius, fitRadius});
}

}  // namespace vpsim::kernel
