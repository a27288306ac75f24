// Pictures of a beam kernel, after seed 000 Fig. 11 (intensity contours with and without
// scattering), Fig. 12 (amplitude and Gaussian radius against depth) and Fig. 13 (the Eq. 12 fit).

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
    writeSvgLinePlot(directory + "/amplitude_vs_depth.svg", "Beam amplitude Ie(0, z) against depth",
                     "depth z (um)", "Ie(0, z) (mW/mm^2)",
                     {mcAmplitude, blAmplitude, fitAmplitude});
    writeSvgLinePlot(directory + "/radius_vs_depth.svg", "Gaussian radius We(z) against depth",
                     "depth z (um)", "We (um)", {mcRadius, blRadius, fitRadius});
}

}  // namespace vpsim::kernel
