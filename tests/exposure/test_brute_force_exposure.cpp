// Issue 22 item 6: both engines against brute force on a small case. Every scan sample (0.5 um
// apart along each vector, independent of the engines' own quarter-cell sampling) is summed
// against every voxel centre through seed 000 Eq. 12 with print-through: a sample of energy e
// on the top of layer j gives a voxel at depth d below that surface e (2 / (pi W^2))
// exp(-2 r^2 / W^2) exp(-d / De). The engines discretise the deposit (bilinear splat on 10 um
// cells), the blur (sampled, truncated and renormalised Gaussian) or the table (1 um x 2 um bins);
// on the voxels that decide the cured boundary (brute-force dose within a factor 2 of Ec), both
// must agree within 2.6% of the dose.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "exposure/exposure_test_util.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/exposure/tabulated_engine.h"
#include "vpsim/plan/aces/aces.h"

using namespace vpsim;
using namespace vpsim::exposure;

namespace {

constexpr double PI = 3.14159265358979323846;
constexpr double W = 0.05, De = 0.04, H = 0.05;

plan::ScanPlan smallPlan() {
    plan::ScanPlan plan;
    plan.machine.layerThickness = H;
    const double sides[3] = {0.3, 0.3, 0.2};  // the top layer narrower: a down-facing step
    for (int k = 0; k < 3; ++k) {
        plan::LayerPlan layer;
        layer.z = (k + 1) * H;
        const double s = sides[k];
        layer.vectors =
            plan::hatchRegion(geometry::PolygonSet::rectangle({-s / 2, -s / 2}, {s / 2, s / 2}),
                              0.03, 0.0, 10.0, 500.0);
        plan.layers.push_back(layer);
    }
    return plan;
}

/// Brute-force dose of every voxel, [layer][slice][cell].
std::vector<std::vector<std::vector<double>>> bruteForce(const plan::ScanPlan& plan,
                                                         const ExposureGrid& grid) {
    const int n = grid.slicesPerLayer, layers = int(plan.layers.size());
    std::vector<std::vector<std::vector<double>>> dose(
        layers,
        std::vector<std::vector<double>>(n, std::vector<double>(size_t(grid.nx) * grid.ny)));
    const SurfaceGrid cells = grid.surface();
    for (int j = 0; j < layers; ++j)
        for (const auto& v : plan.layers[j].vectors) {
            const double length = std::hypot(v.x1 - v.x0, v.y1 - v.y0);
            const int samples = std::max(1, int(std::ceil(length / 0.0005)));
            const double e = v.power / v.speed * length / samples;
            for (int m = 0; m < samples; ++m) {
                const double t = (m + 0.5) / samples;
                const double x = v.x0 + t * (v.x1 - v.x0), y = v.y0 + t * (v.y1 - v.y0);
                for (int c = 0; c < grid.nx * grid.ny; ++c) {
                    const double dx = cells.centreX(c % grid.nx) - x,
                                 dy = cells.centreY(c / grid.nx) - y;
                    const double lateral =
                        e * 2 / (PI * W * W) * std::exp(-2 * (dx * dx + dy * dy) / (W * W));
                    if (lateral < 1e-12) continue;
                    for (int k = 0; k <= j; ++k)
                        for (int s = 0; s < n; ++s) {
                            const double depth = (j - k) * H + (s + 0.5) * H / n;
                            dose[k][s][c] += lateral * std::exp(-depth / De);
                        }
                }
            }
        }
    return dose;
}

/// Largest |engine - brute| / brute over voxels with brute dose in [Ec / 2, 2 Ec], Ec half the
/// brute-force maximum (the cure band).
double cureBandError(const std::vector<std::vector<SurfaceGrid>>& engine,
                     const std::vector<std::vector<std::vector<double>>>& brute) {
    double peak = 0;
    for (const auto& layer : brute)
        for (const auto& slice : layer)
            peak = std::max(peak, *std::max_element(slice.begin(), slice.end()));
    const double ec = 0.5 * peak;
    double worst = 0;
    for (size_t k = 0; k < brute.size(); ++k)
        for (size_t s = 0; s < brute[k].size(); ++s)
            for (size_t c = 0; c < brute[k][s].size(); ++c) {
                const double b = brute[k][s][c];
                if (b < 0.5 * ec || b > 2 * ec) continue;
                worst = std::max(worst, std::abs(engine[k][s].values[c] - b) / b);
            }
    return worst;
}

}  // namespace

TEST_CASE("both engines agree with the brute-force sum of Eq. 12 in the cure band",
          "[exposure][tabulated]") {
    const plan::ScanPlan plan = smallPlan();
    const ExposureGrid grid = ExposureGrid::covering(-0.15, -0.15, 0.15, 0.15, 0.12, 0.01, 2);
    const auto brute = bruteForce(plan, grid);
    ExposureEngine fitted(grid, kernel::FittedBeam{W, De}, H);
    const double A = 2 * 10.0 / (PI * W * W);
    TabulatedExposureEngine tabulated(
        grid,
        test::tableKernel(10.0, 0.001, uint32_t(std::ceil(3 * W / 0.001)), 0.002,
                          uint32_t(std::ceil(8 * De / 0.002)),
                          [=](double r, double z) {
                              return A * std::exp(-2 * r * r / (W * W)) * std::exp(-z / De);
                          }),
        H);
    const double fittedError = cureBandError(test::exposeAll(fitted, plan), brute);
    const double tabulatedError = cureBandError(test::exposeAll(tabulated, plan), brute);
    INFO("cure-band error against brute force: fitted " << fittedError << ", tabulated "
                                                        << tabulatedError);
    CHECK(fittedError < 0.026);
    CHECK(tabulatedError < 0.026);
    WARN("cure-band error against brute force: fitted " << fittedError << ", tabulated "
                                                        << tabulatedError);
}
