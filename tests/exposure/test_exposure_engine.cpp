#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "exposure/exposure_gpu.h"
#include "exposure/exposure_test_util.h"
#include "support/gpu_test.h"
#include "vpsim/core/error.h"
#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"

using namespace vpsim;
using namespace vpsim::exposure;

namespace {

const kernel::FittedBeam BEAM{0.05, 0.12};  // W = 50 um (seed 000's W0), De = 120 um

plan::LayerPlan lineLayer(double z, double y, double power, double speed) {
    plan::LayerPlan layer;
    layer.z = z;
    layer.vectors.push_back({-1.0, y, 1.0, y, power, speed});
    return layer;
}

}  // namespace

// A scanned line's exposure across the line is seed 000 Eq. C.6:
// Es(y) = sqrt(2/pi) P / (W V) exp(-2 y^2 / W^2). Tolerance 1%: the 5 um grid samples a 50 um
// Gaussian with the line on a row of cell centres, so the discretisation error is ~(pitch/W)^2/12.
TEST_CASE("a single scanned line matches the analytic line exposure of Eq. C.6", "[exposure]") {
    const double pitch = 0.005, P = 10.0, V = 100.0;
    ExposureGrid grid = ExposureGrid::covering(-0.5, -0.5, 0.5, 0.5, 0.0, pitch, 1);
    ExposureEngine engine(grid, BEAM, 0.05);
    SurfaceGrid deposit(grid.nx, grid.ny, grid.originX, grid.originY, pitch);
    const double lineY = 0.0025;  // centre of a cell row
    depositLayer(lineLayer(0.05, lineY, P, V), deposit);
    SurfaceGrid map = engine.exposureMap(deposit);
    const double W = BEAM.radius;
    const int i = grid.nx / 2;
    for (int j = 0; j < grid.ny; ++j) {
        double y = map.centreY(j) - lineY;
        if (std::abs(y) > 1.5 * W) continue;
        double analytic = std::sqrt(2.0 / M_PI) * P / (W * V) * std::exp(-2.0 * y * y / (W * W));
        INFO("y = " << y);
        CHECK(map.at(i, j) == Approx(analytic).epsilon(0.01));
    }
}

// ACES: parallel lines at hatch spacing hs reach the plateau Ep = P / (V hs) (Eq. C.8). With
// hs = W/2 the ripple of Eq. C.7 is below 1e-6, so 0.5% covers the discretisation.
TEST_CASE("an ACES field reaches the plateau exposure of Eq. C.8", "[exposure]") {
    const double pitch = 0.005, P = 10.0, V = 200.0, hs = 0.025;
    ExposureGrid grid = ExposureGrid::covering(-0.6, -0.6, 0.6, 0.6, 0.0, pitch, 1);
    ExposureEngine engine(grid, BEAM, 0.05);
    SurfaceGrid deposit(grid.nx, grid.ny, grid.originX, grid.originY, pitch);
    plan::LayerPlan layer;
    for (double y = -0.5; y <= 0.5 + 1e-9; y += hs)
        layer.vectors.push_back({-0.5, y, 0.5, y, P, V});
    depositLayer(layer, deposit);
    SurfaceGrid map = engine.exposureMap(deposit);
    const double plateau = P / (V * hs);
    for (int j = grid.ny / 2 - 20; j <= grid.ny / 2 + 20; ++j)
        CHECK(map.at(grid.nx / 2, j) == Approx(plateau).epsilon(0.005));
    // Energy is conserved by the blur (renormalised taps): float sums over 57,600 cells -> 1e-5.
    CHECK(map.totalEnergy() == Approx(deposit.totalEnergy()).epsilon(1e-5));
}

// Eq. 21: the recursion must equal the direct sum over later layers of E_map,j exp(-(depth)/De).
// Tolerance 1e-5 relative: float accumulation over 6 layers.
TEST_CASE("the print-through recursion equals the direct sum over layers", "[exposure]") {
    const double h = 0.04, pitch = 0.01;
    plan::ScanPlan plan = test::randomPlan(6, h, 3);
    ExposureGrid grid = ExposureGrid::covering(-0.4, -0.4, 0.4, 0.4, 0.15, pitch, 2);
    ExposureEngine engine(grid, BEAM, h);
    auto slices = test::exposeAll(engine, plan);
    std::vector<SurfaceGrid> maps;
    for (const auto& layer : plan.layers) {
        SurfaceGrid deposit(grid.nx, grid.ny, grid.originX, grid.originY, pitch);
        depositLayer(layer, deposit);
        maps.push_back(engine.exposureMap(deposit));
    }
    for (int k = 0; k < 6; ++k)
        for (int s = 0; s < 2; ++s) {
            double z = plan.layers[k].z - (s + 0.5) * h / 2;
            for (size_t c = 0; c < maps[0].values.size(); c += 37) {
                double direct = 0;
                for (int j = k; j < 6; ++j)
                    direct += maps[j].values[c] *
                              std::exp(-(plan.layers[j].z - z) / BEAM.attenuationLength);
                CHECK(slices[k][s].values[c] == Approx(direct).epsilon(1e-5).margin(1e-9));
            }
        }
}

// Exposure is linear in the plan (test::requireSuperposition).
TEST_CASE("exposure obeys superposition and linearity", "[exposure]") {
    ExposureGrid grid = ExposureGrid::covering(-0.4, -0.4, 0.4, 0.4, 0.1, 0.01, 1);
    ExposureEngine engine(grid, BEAM, 0.05);
    test::requireSuperposition(engine, 3, 0.3, 13);
}

// The shader path and the CPU path compile the same exposure.glsl; they may differ only by float
// rounding and exp() implementations: 1e-5 relative.
// Both ways the host reaches the device: mapped memory (lavapipe) and staging copies (a discrete
// GPU's path, test::stagedGpuContext).
TEST_CASE("GPU and CPU exposure agree", "[exposure][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(shared);
    const double h = 0.05;
    plan::ScanPlan plan = test::randomPlan(4, h, 21);
    ExposureGrid grid = ExposureGrid::covering(-0.4, -0.4, 0.4, 0.4, 0.1, 0.01, 2);
    ExposureEngine cpu(grid, BEAM, h);
    auto ec = test::exposeAll(cpu, plan);
    for (const auto& ctx : {shared, test::stagedGpuContext()}) {
        ExposureEngine gpu(grid, BEAM, h, ctx);
        REQUIRE(gpu.usesGpu());
        auto eg = test::exposeAll(gpu, plan);
        for (int k = 0; k < 4; ++k)
            for (int s = 0; s < 2; ++s)
                for (size_t c = 0; c < ec[k][s].values.size(); ++c)
                    REQUIRE(eg[k][s].values[c] ==
                            Approx(ec[k][s].values[c]).epsilon(1e-5).margin(1e-8));
        VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
    }
}

// The shader blurs strips of rows, each from the 2 halfWidth rows above it: a grid taller than a
// strip (about 32 rows on a GPU; on lavapipe with two or more threads, one strip per thread here,
// blurStripRows) checks the seams, and a blur of half-width 32 cells (a 50 um beam on a 2.75 um
// grid), the widest the shader takes, its largest state.
TEST_CASE("the shader blur agrees with the CPU path across its strips and at its widest",
          "[exposure][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    const double h = 0.05;
    struct Case {
        ExposureGrid grid;
        plan::ScanPlan plan;
    };
    const Case cases[] = {{ExposureGrid::covering(-0.2, -1.5, 0.2, 1.5, 0.1, 0.01, 2),
                           test::randomPlan(3, h, 31, 1.4)},
                          {ExposureGrid::covering(-0.15, -0.15, 0.15, 0.15, 0.05, 0.00275, 1),
                           test::randomPlan(2, h, 32, 0.15)}};
    const gpu::DeviceInfo& device = ctx->info();
    const int tallReach = blurHalfWidth(BEAM.radius, cases[0].grid.pitch);
    if (device.hostThreads == 1)
        WARN("one thread runs this CPU driver's workgroups: one strip, no seams checked");
    else
        REQUIRE(blurStripRows(device, 1, uint32_t(cases[0].grid.ny), tallReach) <
                uint32_t(cases[0].grid.ny));
    for (const Case& c : cases) {
        ExposureEngine cpu(c.grid, BEAM, h), gpu(c.grid, BEAM, h, ctx);
        REQUIRE(gpu.usesGpu());
        auto ec = test::exposeAll(cpu, c.plan), eg = test::exposeAll(gpu, c.plan);
        // Exposed rows in the lower half of the grid (on the tall grid, the second strip) too.
        double peak = 0, peakBelow = 0;
        for (size_t k = 0; k < ec.size(); ++k)
            for (size_t s = 0; s < ec[k].size(); ++s)
                for (size_t i = 0; i < ec[k][s].values.size(); ++i) {
                    const double v = ec[k][s].values[i];
                    peak = std::max(peak, v);
                    if (i / size_t(c.grid.nx) >= size_t(c.grid.ny) / 2)
                        peakBelow = std::max(peakBelow, v);
                    REQUIRE(eg[k][s].values[i] ==
                            Approx(ec[k][s].values[i]).epsilon(1e-5).margin(1e-8));
                }
        CHECK(peakBelow > 0.1 * peak);
    }
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}

// The strips' rows: on a GPU about 32; on a CPU driver the strip count whose busiest thread has the
// fewest steps (rows plus the lead of 2 halfWidth rows per strip, workgroups dealt out whole), the
// same as counting every strip count's steps by hand; the rows always cover the grid.
TEST_CASE("the blur's strips keep the busiest thread of a CPU driver least busy", "[exposure]") {
    gpu::DeviceInfo gpuDevice, cpuDevice;
    gpuDevice.type = "discrete";
    cpuDevice.type = "cpu";
    // Rows in whole iterations of the shader's loop, 2 halfWidth + 1 = 25 rows here (its y pass
    // gathers from a ring of rows), 8 past 16 cells each side.
    CHECK(blurStripRows(gpuDevice, 17, 1030, 12) == 50);  // 32 rows, rounded up
    cpuDevice.hostThreads = 2;
    CHECK(blurStripRows(cpuDevice, 17, 1030, 12) == 525);  // 2 strips of the bench's block
    cpuDevice.hostThreads = 1;
    CHECK(blurStripRows(cpuDevice, 17, 1030, 12) == 1050);  // one strip: leads only cost
    CHECK(blurStripRows(cpuDevice, 17, 1030, 17) == 1032);
    std::mt19937 rng(7);
    for (int trial = 0; trial < 300; ++trial) {
        const uint32_t threads = 1 + rng() % 32, columns = 1 + rng() % 40, ny = 1 + rng() % 3000;
        const int halfWidth = 1 + int(rng() % 32);
        cpuDevice.hostThreads = threads;
        const uint32_t rows = blurStripRows(cpuDevice, columns, ny, halfWidth);
        const uint32_t loop = blurStripSteps(halfWidth);
        REQUIRE(loop == (halfWidth <= 16 ? 2 * uint32_t(halfWidth) + 1 : 8));
        REQUIRE(rows % loop == 0);
        const uint32_t strips = (ny + rows - 1) / rows;  // as the engine dispatches them
        auto steps = [&](uint32_t n, uint32_t rowsEach) {
            return (uint64_t(columns) * n + threads - 1) / threads * (rowsEach + 2 * halfWidth);
        };
        uint64_t best = UINT64_MAX;
        for (uint32_t n = 1; n <= ny; ++n)
            best = std::min(best, steps(n, ((ny + n - 1) / n + loop - 1) / loop * loop));
        REQUIRE(steps(strips, rows) == best);
    }
}

// Wider blurs cost the shader more than they save (EXPOSURE_BLUR_MAX_HALF_WIDTH): the engine
// takes the CPU path, with the same figures, instead of refusing the run.
TEST_CASE("a blur wider than the shader takes is exposed on the CPU path", "[exposure][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    const double h = 0.05;
    ExposureGrid grid = ExposureGrid::covering(-0.1, -0.1, 0.1, 0.1, 0.05, 0.0025, 1);
    plan::ScanPlan plan = test::randomPlan(1, h, 33, 0.1);
    ExposureEngine cpu(grid, BEAM, h), wide(grid, BEAM, h, ctx);
    CHECK_FALSE(wide.usesGpu());
    auto ec = test::exposeAll(cpu, plan), ew = test::exposeAll(wide, plan);
    CHECK(ew[0][0].values == ec[0][0].values);
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}

// The fitted blur stores its outputs as 64-bit words (shaders/include/float8_io.glsl): on a device
// without shaderInt64 the engine exposes on the CPU path, with the same figures, instead of
// making a pipeline the device cannot run (the validation layer would object).
TEST_CASE("a device without shaderInt64 exposes on the CPU path", "[exposure][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    gpu::ContextOptions options;
    options.validation = true;
    options.int64 = false;
    const auto noInt64 = gpu::Context::create(options);
    REQUIRE_FALSE(noInt64->info().int64);
    const double h = 0.05;
    ExposureGrid grid = ExposureGrid::covering(-0.1, -0.1, 0.1, 0.1, 0.05, 0.01, 1);
    plan::ScanPlan plan = test::randomPlan(1, h, 33, 0.1);
    ExposureEngine cpu(grid, BEAM, h), gpu(grid, BEAM, h, ctx), fallback(grid, BEAM, h, noInt64);
    CHECK(gpu.usesGpu());
    CHECK_FALSE(fallback.usesGpu());
    auto ec = test::exposeAll(cpu, plan), ef = test::exposeAll(fallback, plan);
    CHECK(ef[0][0].values == ec[0][0].values);
    VPSIM_REQUIRE_VALIDATION_CLEAN(noInt64);
}

// The shader path keeps the running sum on the device: a one-layer map taken in the middle of a run
// (from a sink) must not leak into the run, and a second run must start afresh. A grid whose sides
// are not multiples of the shader's blocks checks the padding.
TEST_CASE("the shader path's device state survives a layer map and a second run",
          "[exposure][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(shared);
    const double h = 0.05;
    plan::ScanPlan plan = test::randomPlan(4, h, 23);
    ExposureGrid grid = ExposureGrid::covering(-0.37, -0.41, 0.4, 0.33, 0.1, 0.01, 2);
    ExposureEngine cpu(grid, BEAM, h);
    SurfaceGrid deposit = grid.surface();
    depositLayer(plan.layers[1], deposit);
    auto expected = test::exposeAll(cpu, plan);
    const SurfaceGrid mapCpu = cpu.layerMap(deposit, 0.02);
    // Mapped memory and staging copies: the map mid-run writes over the run's S and R in the
    // host mirrors either way.
    for (const auto& ctx : {shared, test::stagedGpuContext()}) {
        ExposureEngine gpu(grid, BEAM, h, ctx);
        std::vector<std::vector<SurfaceGrid>> got(4, std::vector<SurfaceGrid>(2));
        SurfaceGrid map;
        gpu.run(plan, [&](const ExposureSlice& s) {
            got[s.layer][s.slice] = *s.values;
            if (s.layer == 2 && s.slice == 0) map = gpu.layerMap(deposit, 0.02);
        });
        auto again = test::exposeAll(gpu, plan);
        for (size_t c = 0; c < mapCpu.values.size(); ++c)
            REQUIRE(map.values[c] == Approx(mapCpu.values[c]).epsilon(1e-5).margin(1e-8));
        for (int k = 0; k < 4; ++k)
            for (int s = 0; s < 2; ++s)
                for (size_t c = 0; c < expected[k][s].values.size(); ++c) {
                    REQUIRE(got[k][s].values[c] ==
                            Approx(expected[k][s].values[c]).epsilon(1e-5).margin(1e-8));
                    REQUIRE(again[k][s].values[c] ==
                            Approx(expected[k][s].values[c]).epsilon(1e-5).margin(1e-8));
                }
        VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
    }
}

TEST_CASE("impossible exposure parameters are refused clearly", "[exposure]") {
    ExposureGrid grid = ExposureGrid::covering(0, 0, 1, 1, 0, 0.01, 1);
    CHECK_THROWS_AS(ExposureEngine(grid, {0.0, 0.1}, 0.05), InputError);
    CHECK_THROWS_AS(ExposureEngine(grid, {0.05, -1.0}, 0.05), InputError);
    CHECK_THROWS_AS(ExposureEngine(grid, BEAM, 0.0), InputError);
    CHECK_THROWS_WITH(ExposureEngine(grid, {0.005, 0.1}, 0.05),
                      Catch::Matchers::Contains("coarser than the beam"));
    ExposureGrid huge = ExposureGrid::covering(0, 0, 1000, 1000, 0, 0.01, 1);
    CHECK_THROWS_WITH(ExposureEngine(huge, BEAM, 0.05),
                      Catch::Matchers::Contains("use a coarser pitch"));
}

// The beam efficiency scales the exposure once (linearity in the kernel amplitude), on both paths.
TEST_CASE("the beam efficiency scales the exposure linearly", "[exposure][gpu]") {
    VPSIM_GPU_CONTEXT_OR_SKIP(ctx);
    plan::ScanPlan plan = test::randomPlan(2, 0.05, 5);
    ExposureGrid grid = ExposureGrid::covering(-0.4, -0.4, 0.4, 0.4, 0.1, 0.01, 1);
    kernel::FittedBeam scaled = BEAM;
    scaled.efficiency = 2.5;
    for (auto context : {std::shared_ptr<gpu::Context>(), ctx}) {
        ExposureEngine plain(grid, BEAM, 0.05, context), efficient(grid, scaled, 0.05, context);
        auto a = test::exposeAll(plain, plan), b = test::exposeAll(efficient, plan);
        for (size_t c = 0; c < a[0][0].values.size(); c += 7)
            CHECK(b[0][0].values[c] == Approx(2.5 * a[0][0].values[c]).epsilon(1e-5).margin(1e-8));
    }
    VPSIM_REQUIRE_VALIDATION_CLEAN(ctx);
}
