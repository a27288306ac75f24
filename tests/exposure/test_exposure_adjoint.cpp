// The exposure model's adjoints: <A x, y> = <x, A^T y> for both engines and both operators (one
// layer's map at several depths, and the whole stack with print-through), and the operator
// form of the forward model equals the streaming run.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>

#include "exposure/exposure_test_util.h"
#include "vpsim/core/error.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/exposure/tabulated_engine.h"

using namespace vpsim;
using namespace vpsim::exposure;

namespace {

constexpr double H = 0.03;  // layer thickness, mm

ExposureGrid smallGrid() {
    ExposureGrid g;
    g.nx = 48;
    g.ny = 37;  // not square, so transposed indexing would show
    g.originX = -0.24;
    g.originY = -0.18;
    g.pitch = 0.01;
    g.slicesPerLayer = 3;
    return g;
}

SurfaceGrid randomGrid(const ExposureGrid& g, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    SurfaceGrid s = g.surface();
    for (float& v : s.values) v = u(rng);
    return s;
}

std::unique_ptr<ExposureModel> makeEngine(bool tabulated) {
    const ExposureGrid g = smallGrid();
    if (!tabulated) return std::make_unique<ExposureEngine>(g, kernel::FittedBeam{0.04, 0.05}, H);
    // A kernel that widens with depth (so it is not separable) and decays over ~2 layers.
    kernel::BeamKernel k = test::tableKernel(10.0, 0.004, 30, 0.005, 24, [](double r, double z) {
        double w = 0.03 + 0.5 * z;
        return 2 * 10.0 / (M_PI * w * w) * std::exp(-2 * r * r / (w * w) - z / 0.04);
    });
    return std::make_unique<TabulatedExposureEngine>(g, k, H);
}

/// Relative mismatch of the two sides of the adjoint identity.
double relativeGap(double lhs, double rhs) {
    return std::abs(lhs - rhs) / std::abs(lhs);
}

}  // namespace

TEST_CASE("one layer's map and its adjoint satisfy <A x, y> = <x, A^T y> (both engines)") {
    for (bool tabulated : {false, true}) {
        auto engine = makeEngine(tabulated);
        std::mt19937 rng(7);
        for (double depth : {0.0, 0.004, 0.017, 0.052}) {
            SurfaceGrid x = randomGrid(engine->grid(), rng), y = randomGrid(engine->grid(), rng);
            double lhs = dot(engine->layerMap(x, depth), y);
            double rhs = dot(x, engine->layerMapAdjoint(y, depth));
            INFO(engine->name() << " at depth " << depth << " mm: " << lhs << " vs " << rhs);
            REQUIRE(lhs > 0);
            // Float sums over ~1800 cells of ~100 taps: 1e-5 relative is ~10x their rounding.
            REQUIRE(relativeGap(lhs, rhs) < 1e-5);
        }
    }
}

TEST_CASE("the whole stack and its adjoint satisfy <A x, y> = <x, A^T y> (both engines)") {
    for (bool tabulated : {false, true}) {
        auto engine = makeEngine(tabulated);
        std::mt19937 rng(11);
        const int layers = 5;
        std::vector<SurfaceGrid> x;
        for (int k = 0; k < layers; ++k) x.push_back(randomGrid(engine->grid(), rng));
        ExposureField y;
        for (int i = 0; i < layers * engine->grid().slicesPerLayer; ++i)
            y.push_back(randomGrid(engine->grid(), rng));
        double lhs = dot(engine->stack(x), y);
        std::vector<SurfaceGrid> adjoint = engine->stackAdjoint(y);
        REQUIRE(adjoint.size() == size_t(layers));
        double rhs = 0;
        for (int k = 0; k < layers; ++k) rhs += dot(x[k], adjoint[k]);
        INFO(engine->name() << ": " << lhs << " vs " << rhs);
        REQUIRE(relativeGap(lhs, rhs) < 1e-5);
    }
}

TEST_CASE("the operator form of the forward model equals the streaming run of a plan") {
    for (bool tabulated : {false, true}) {
        auto engine = makeEngine(tabulated);
        plan::ScanPlan plan = test::randomPlan(4, H, 3, 0.15);
        std::vector<SurfaceGrid> deposits;
        for (const auto& layer : plan.layers) {
            SurfaceGrid d = engine->grid().surface();
            depositLayer(layer, d);
            deposits.push_back(d);
        }
        ExposureField field = engine->stack(deposits);
        auto slices = test::exposeAll(*engine, plan);
        const int n = engine->grid().slicesPerLayer;
        for (size_t k = 0; k < slices.size(); ++k)
            for (int s = 0; s < n; ++s)
                REQUIRE(field[k * n + s].values == slices[k][s].values);  // the same arithmetic
    }
}

TEST_CASE("an adjoint field that is not whole layers of the grid is refused") {
    auto engine = makeEngine(false);
    ExposureField field(4, engine->grid().surface());  // 4 slices, 3 per layer
    REQUIRE_THROWS_AS(engine->stackAdjoint(field), InputError);
}
