// Figures of a beam kernel, after seed 000 Fig. 11 (intensity contours with and without
// scattering), Fig. 12 (amplitude and Gaussian radius against depth) and Fig. 13 (the Eq. 12 fit),
// through the plotting layer (vpsim/plot/plot.h): each as .svg and .png, axes in um, intensities
// in mW/mm^2.

#include <algorithm>
#include <cmath>
#include <functional>

#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/plot/plot.h"

namespace vpsim::kernel {

namespace {

constexpr double UM = 1000.0;
constexpr int TARGET_CELLS =
    300;  // cells along the longer side of an intensity map (bins are coarser)
/// Iso-intensity levels in every figure, as fractions of the unscattered peak I0, so the
/// contours compare directly between figures.
const std::vector<double> FRACTIONS = {0.1, 0.2, 0.4, 0.8};

using Field = std::function<double(double r, double z)>;

std::string percent(double fraction) {
    return std::to_string(int(std::lround(fraction * 100))) + "%";
}

/// A map of field(r, z) in the r-z plane: r from -rMax to rMax, depth plotted as -z so the
/// surface is on top, at the true aspect ratio, with the iso-intensity contours.
void writeField(const std::string& stem, const std::string& title, const BeamKernel& k,
                const Field& field, double hi, double peakNoScatter) {
    const double rMax = k.rBin * k.rBins, zMax = k.zBin * k.zBins;
    const double pixel = std::max(2 * rMax, zMax) / TARGET_CELLS;
    plot::MapFigure f;
    f.title = title;
    f.xLabel = "r (µm)";
    f.yLabel = "-z, depth below the surface (µm)";
    f.scaleUnit = "µm";
    f.nx = std::max(1, int(std::lround(2 * rMax / pixel)));
    f.ny = std::max(1, int(std::lround(zMax / pixel)));
    f.x0 = -rMax * UM, f.x1 = rMax * UM, f.y0 = -zMax * UM, f.y1 = 0;
    const double dr = 2 * rMax / f.nx, dz = zMax / f.ny;
    f.values.resize(size_t(f.nx) * f.ny);
    for (int j = 0; j < f.ny; ++j)  // row 0 at the bottom, the deepest
        for (int i = 0; i < f.nx; ++i)
            f.values[size_t(j) * f.nx + i] =
                float(field(std::abs(-rMax + (i + 0.5) * dr), zMax - (j + 0.5) * dz));
    f.scale = {plot::ColourMap::Sequential, 0.0, hi, "I(r, z) (mW/mm#u2#d)", false, false};
    const plot::Rgb colours[] = {{80, 220, 255}, {255, 190, 60}, {240, 80, 60}, {150, 20, 40}};
    for (size_t i = 0; i < FRACTIONS.size(); ++i)
        f.outlines.push_back({percent(FRACTIONS[i]) + " of I#d0#u",
                              {},
                              FRACTIONS[i] * peakNoScatter,
                              colours[i % 4],
                              false});
    f.note = "I#d0#u = 2P(1-R#dsp#u)/(#gpW#d0#u#u2#d) = " + formatNumber(peakNoScatter, 4) +
             " mW/mm#u2#d, the unscattered peak";
    plot::writeMapFigure(stem, f);
}

/// Outermost radius where field(r, z) >= level, interpolated inside the crossing step; -1 when
/// the field is below the level at every r.
double levelRadius(const Field& field, double z, double level, double rMax, double step) {
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
plot::Curve contourCurve(const BeamKernel& k, const Field& field, double level,
                         const std::string& label, plot::Rgb colour, bool dashed) {
    plot::Curve curve{label, {}, {}, colour, dashed};
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
        curve.x.push_back(-r * UM);
        curve.y.push_back(-z * UM);
    }
    for (auto it = side.rbegin(); it != side.rend(); ++it) {
        curve.x.push_back(it->first * UM);
        curve.y.push_back(-it->second * UM);
    }
    return curve;
}

/// Seed 000 Fig. 11 / 13: contours of `a` (solid) and `b` (dashed) at the same absolute levels,
/// r and z to the same scale.
void writeContours(const std::string& stem, const std::string& title, const BeamKernel& k,
                   const Field& a, const std::string& aName, const Field& b,
                   const std::string& bName, double reference) {
    plot::LineFigure f;
    f.title = title;
    f.xLabel = "r (µm)";
    f.yLabel = "-z, depth below the surface (µm)";
    f.equalAspect = true;
    for (size_t i = 0; i < FRACTIONS.size(); ++i) {
        const double level = FRACTIONS[i] * reference;
        const std::string pct = percent(FRACTIONS[i]);
        f.curves.push_back(
            contourCurve(k, a, level, aName + " " + pct, plot::paletteColour(i), false));
        f.curves.push_back(
            contourCurve(k, b, level, bName + " " + pct, plot::paletteColour(i), true));
    }
    plot::writeLineFigure(stem, f);
}

/// Seed 000 Fig. 12: Ie(0, z) and We(z) of the table, without scattering and of the fit.
void writeDepthProfiles(const std::string& directory, const BeamKernel& k) {
    plot::Curve mcAmplitude{"Monte Carlo Ie(0, z)"}, mcRadius{"Monte Carlo We(z)"};
    plot::Curve blAmplitude{"no scattering (Beer-Lambert)"}, blRadius{"no scattering W#d0#u"};
    plot::Curve fitAmplitude{"Eq. 12 fit"}, fitRadius{"Eq. 12 We#d3D#u"};
    blAmplitude.colour = blRadius.colour = plot::paletteColour(1);
    fitAmplitude.colour = fitRadius.colour = plot::paletteColour(2);
    fitAmplitude.dashed = fitRadius.dashed = true;
    for (uint32_t iz = 0; iz < k.zBins; ++iz) {
        const double z = (iz + 0.5) * k.zBin;
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
    const plot::Curve zmaxLine{
        "z#dmax#u", {k.zmax * UM, k.zmax * UM}, {0.0, top}, {85, 85, 85}, true};
    plot::writeLineFigure(directory + "/amplitude_vs_depth",
                          {"Beam amplitude Ie(0, z) against depth (Fig. 12)",
                           "depth z (µm)",
                           "Ie(0, z) (mW/mm#u2#d)",
                           {mcAmplitude, blAmplitude, fitAmplitude, zmaxLine}});
    plot::writeLineFigure(directory + "/radius_vs_depth",
                          {"Gaussian radius We(z) against depth (Fig. 12)",
                           "depth z (µm)",
                           "We (µm)",
                           {mcRadius, blRadius, fitRadius}});
}

}  // namespace

void writeKernelFigures(const std::string& directory, const BeamKernel& k) {
    createDirectories(directory);
    const double peakNoScatter = k.beerLambert(0, 0);
    const double peakTable = *std::max_element(k.intensity.begin(), k.intensity.end());
    const double hi = std::max(peakNoScatter, peakTable);  // one scale for the three maps
    const Field table = [&k](double r, double z) { return k.sample(r, z); };
    const Field noScatter = [&k](double r, double z) { return k.beerLambert(r, z); };
    const Field fit = [&k](double r, double z) { return k.fitted(r, z); };
    writeField(directory + "/intensity_scattered",
               "Beam kernel I(r, z) with scattering (Monte Carlo)", k, table, hi, peakNoScatter);
    writeField(directory + "/intensity_no_scattering",
               "Beam kernel I(r, z) without scattering (Beer-Lambert)", k, noScatter, hi,
               peakNoScatter);
    writeField(directory + "/intensity_fit", "Beam kernel I(r, z) of the Eq. 12 fit", k, fit, hi,
               peakNoScatter);
    writeContours(directory + "/contours_scattering",
                  "Iso-intensity contours with and without scattering (Fig. 11), % of I#d0#u", k,
                  table, "MC", noScatter, "no scatt.", peakNoScatter);
    writeContours(directory + "/contours_fit",
                  "Monte Carlo table against the Eq. 12 fit (Fig. 13), % of I#d0#u", k, table, "MC",
                  fit, "Eq. 12", peakNoScatter);
    writeDepthProfiles(directory, k);
}

}  // namespace vpsim::kernel
