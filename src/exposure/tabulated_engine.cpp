#include "vpsim/exposure/tabulated_engine.h"

#include "exposure/exposure_glsl.h"
#include "exposure/row_extents.h"
#include "exposure/stencil_gather.h"
#include "exposure/tabulated_gpu.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>

#include <tbb/parallel_for.h>

#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"
#include "vpsim/exposure/deposit.h"

namespace vpsim::exposure {
namespace {

/// Truncation: each stencil keeps all but this fraction of its depth plane's power (radius
/// Reff(d)), and the stencils stop where all but this fraction of the power summed over the
/// slice depths is inside, so about 1 - 2 x 0.002 of the kernel's energy is kept (>= 99.5%,
/// measured by keptEnergyFraction()).
constexpr double RADIAL_ENERGY_LOSS = 0.002;
constexpr double DEPTH_ENERGY_LOSS = 0.002;
constexpr int RADIAL_STEPS_PER_BIN = 8;  ///< radial integration steps per table bin
constexpr int SUBSAMPLES = 4;            ///< per cell side: the cell average matters near the axis

/// The kernel's table with its extents (lookups through kernel::BeamKernel::sample: bilinear
/// between bin centres, nearest at the edges, 0 outside).
class KernelTable {
public:
    explicit KernelTable(const kernel::BeamKernel& k) : mK(k) {}
    double sample(double r, double z) const { return mK.sample(r, z); }
    double radialExtent() const { return mK.rBin * mK.rBins; }
    double depthExtent() const { return mK.zBin * mK.zBins; }

private:
    const kernel::BeamKernel& mK;
};

void validateKernel(const kernel::BeamKernel& k) {
    if (!(k.power > 0))
        throw InputError("beam kernel power must be positive (got " + formatQuantity(k.power) +
                         " mW)");
    if (k.rBins == 0 || k.zBins == 0 || k.intensity.empty())
        throw InputError(
            "beam kernel has an empty intensity table: compute it with 'vpsim kernel'");
    if (!(k.rBin > 0) || !(k.zBin > 0)) throw InputError("beam kernel bin sizes must be positive");
    if (k.intensity.size() != size_t(k.rBins) * k.zBins)
        throw InputError(
            "beam kernel table holds " + std::to_string(k.intensity.size()) +
            " values, expected rBins x zBins = " + std::to_string(size_t(k.rBins) * k.zBins));
    bool any = false;
    for (float v : k.intensity) {
        if (!std::isfinite(v) || v < 0)
            throw InputError("beam kernel table holds a negative or non-finite intensity");
        any = any || v > 0;
    }
    if (!any) throw InputError("beam kernel table is all zero: no usable intensity");
}

/// Power through the plane at `depth` inside radius r, 2 pi int_0^r I r' dr' (mW), on a fine
/// radial grid out to the table's radius: cumulative[i] is the power inside i steps of `step`.
std::vector<double> radialPower(const KernelTable& table, double depth, double step) {
    const int steps = int(std::ceil(table.radialExtent() / step));
    std::vector<double> cumulative(size_t(steps) + 1, 0.0);
    for (int i = 0; i < steps; ++i) {
        const double r = (i + 0.5) * step;  // midpoint rule on rings
        cumulative[size_t(i) + 1] =
            cumulative[size_t(i)] + 2 * 3.14159265358979323846 * r * step * table.sample(r, depth);
    }
    return cumulative;
}

/// Reff(d): the smallest radius holding all but RADIAL_ENERGY_LOSS of the plane's power,
/// interpolated inside the step where the cumulative power crosses it.
double effectiveRadius(const std::vector<double>& cumulative, double step) {
    const double total = cumulative.back();
    if (!(total > 0)) return 0;
    const double target = (1 - RADIAL_ENERGY_LOSS) * total;
    for (size_t i = 1; i < cumulative.size(); ++i)
        if (cumulative[i] >= target) {
            const double f =
                (target - cumulative[i - 1]) / std::max(cumulative[i] - cumulative[i - 1], 1e-300);
            return (double(i - 1) + f) * step;
        }
    return (cumulative.size() - 1) * step;
}

/// Stencil count: the first depths holding all but DEPTH_ENERGY_LOSS of the power summed over
/// the slice depths (planePower[m] at depth (m + 0.5) dz); at least one.
int stencilCount(const std::vector<double>& planePower) {
    double total = 0;
    for (double p : planePower) total += p;
    double sum = 0;
    for (size_t m = 0; m < planePower.size(); ++m) {
        sum += planePower[m];
        if (sum >= (1 - DEPTH_ENERGY_LOSS) * total) return int(m) + 1;
    }
    return std::max<int>(1, int(planePower.size()));
}

}  // namespace

/// The CPU gather's state: each stencil's non-zero taps, built once (for the CPU path and the layer
/// maps), and the CPU path's deposit with zero borders, whose storage serves every layer.
struct TabulatedExposureEngine::CpuGather {
    std::vector<StencilTaps> taps;
    PaddedDeposit padded;
};

TabulatedExposureEngine::TabulatedExposureEngine(const ExposureGrid& grid,
                                                 const kernel::BeamKernel& kernel,
                                                 double layerThickness,
                                                 std::shared_ptr<gpu::Context> context)
    : mGrid(grid), mLayerThickness(layerThickness) {
    if (grid.nx <= 0 || grid.ny <= 0) throw InputError("exposure grid has no cells");
    if (!(grid.pitch > 0) || !std::isfinite(grid.pitch))
        throw InputError("exposure grid pitch must be positive");
    if (grid.slicesPerLayer < 1) throw InputError("at least one voxel slice per layer is needed");
    if (!(layerThickness > 0) || !std::isfinite(layerThickness))
        throw InputError("layer thickness must be positive");
    validateKernel(kernel);
    buildStencils(kernel);
    if (context && !GpuState::fits(mStencils, context->info())) {
        // Once per process: a tiled run makes an engine per tile.
        static std::once_flag warned;
        std::call_once(warned, [&] {
            logWarn("tabulated stencils " + std::to_string(reachCells()) +
                    " cells wide each side are wider than the exposure shader takes (" +
                    std::to_string(glsl::STENCIL_MAX_HALF_WIDTH) +
                    ", or the device's shared memory); exposing on the CPU path");
        });
    } else if (context) {
        mGpu = std::make_unique<GpuState>(context, grid.nx, grid.ny, mStencils,
                                          mLayersInFlight * grid.slicesPerLayer);
    }
    mCpu = std::make_unique<CpuGather>();
    for (const DepthStencil& st : mStencils) mCpu->taps.push_back(stencilTaps(st));
}

TabulatedExposureEngine::~TabulatedExposureEngine() = default;

void TabulatedExposureEngine::buildStencils(const kernel::BeamKernel& kernel) {
    const KernelTable table(kernel);
    const int n = mGrid.slicesPerLayer;
    const double dz = mLayerThickness / n, pitch = mGrid.pitch;
    // Every slice centre (m + 0.5) dz inside the table is a candidate; the energy of each plane
    // decides the stencil count and each stencil's radius.
    const double step = kernel.rBin / RADIAL_STEPS_PER_BIN;
    const int candidates = std::max(1, int(std::ceil(table.depthExtent() / dz - 0.5)));
    std::vector<double> planePower(candidates);
    std::vector<double> radii(candidates);
    tbb::parallel_for(0, candidates, [&](int m) {
        const std::vector<double> cumulative = radialPower(table, (m + 0.5) * dz, step);
        planePower[m] = cumulative.back();
        radii[m] = effectiveRadius(cumulative, step);
    });
    const int depthCount = stencilCount(planePower);
    mLayersInFlight = (depthCount + n - 1) / n;

    // Size everything before allocating: the radii fix the stencil sizes.
    mStencils.resize(depthCount);
    double stencilBytes = 0;
    for (int m = 0; m < depthCount; ++m) {
        DepthStencil& st = mStencils[m];
        st.depth = (m + 0.5) * dz;
        st.radius = radii[m];
        // A cell at offset di holds sub-samples down to (|di| - 0.5) pitch from the axis.
        const double halfWidth = std::ceil(st.radius / pitch + 0.5);
        stencilBytes += std::pow(2.0 * halfWidth + 1, 2) * sizeof(float);
        st.halfWidth = int(std::min(halfWidth, 1e6));  // larger ones are refused just below
    }
    // The accumulators, the deposit, the deposit with zero borders the CPU gather reads, and
    // (counted on either path) the shader path's scratch slice, which a group's stencil without
    // a slice of its own adds to (GpuState::scratch).
    const double cells = double(mGrid.nx) * mGrid.ny;
    const double padded = (mGrid.nx + 2.0 * reachCells()) * mGrid.ny;
    mWorkingBytes =
        stencilBytes + (cells * (double(mLayersInFlight) * n + 2) + padded) * sizeof(float);
    if (mWorkingBytes > TABULATED_ENGINE_MAX_BYTES)
        throw ResourceError(
            "tabulated exposure of a " + std::to_string(mGrid.nx) + " x " +
            std::to_string(mGrid.ny) + " grid (pitch " + formatQuantity(pitch * 1e3) +
            " um) with " + std::to_string(depthCount) + " depth stencils over " +
            std::to_string(mLayersInFlight) + " layers needs " + formatBytes(mWorkingBytes) +
            " (limit " + formatBytes(TABULATED_ENGINE_MAX_BYTES) +
            "); use a coarser pitch, fewer slices per layer or a smaller build area");

    // w(di, dj) = pitch^2 <I(r, d)>_cell / P: exposure (mJ/mm^2) per deposit (mJ/mm^2) of a cell.
    // The kernel is radial, so each weight is computed once for 0 <= b <= a (a, b = |di|, |dj|
    // in either order) and copied to the cell's 8 mirror images: the stencil is symmetric bit for
    // bit, which the CPU gather relies on (it folds rows dj and -dj, stencil_gather.h), where
    // sub-samples summed in another order could differ in the last bit.
    const double scale = pitch * pitch / kernel.power;
    tbb::parallel_for(0, depthCount, [&](int m) {
        DepthStencil& st = mStencils[m];
        const int H = st.halfWidth, side = 2 * H + 1;
        st.weights.assign(size_t(side) * side, 0.0f);
        st.rowHalfWidth.assign(side, -1);
        for (int a = 0; a <= H; ++a)
            for (int b = 0; b <= a; ++b) {
                double sum = 0;
                for (int sy = 0; sy < SUBSAMPLES; ++sy)
                    for (int sx = 0; sx < SUBSAMPLES; ++sx) {
                        double x = (a + (sx + 0.5) / SUBSAMPLES - 0.5) * pitch;
                        double y = (b + (sy + 0.5) / SUBSAMPLES - 0.5) * pitch;
                        double r = std::sqrt(x * x + y * y);
                        if (r <= st.radius) sum += table.sample(r, st.depth);
                    }
                const float w = float(scale * sum / (SUBSAMPLES * SUBSAMPLES));
                for (const auto& [di, dj] : {std::pair{a, b},
                                             {-a, b},
                                             {a, -b},
                                             {-a, -b},
                                             {b, a},
                                             {-b, a},
                                             {b, -a},
                                             {-b, -a}}) {
                    st.weights[size_t(dj + H) * side + size_t(di + H)] = w;
                    if (w != 0.0f)
                        st.rowHalfWidth[dj + H] = std::max(st.rowHalfWidth[dj + H], std::abs(di));
                }
            }
    });
    // Kept energy: the stencils' weights (each sums to the power inside Reff / P) against the
    // power through every slice plane inside the table, untruncated.
    double kept = 0, full = 0;
    for (const DepthStencil& st : mStencils)
        for (float w : st.weights) kept += w;
    for (double p : planePower) full += p / kernel.power;
    mKeptEnergyFraction = full > 0 ? kept / full : 1.0;
}

void TabulatedExposureEngine::beginLayers(int layers) {
    if (mGpu) {
        mGpu->clearSlots();  // the slices accumulate on the device; one grid takes each in turn
        mAccumulators.assign(1, mGrid.surface());
    } else {
        mAccumulators.assign(size_t(mLayersInFlight) * mGrid.slicesPerLayer, mGrid.surface());
    }
}

double TabulatedExposureEngine::addLayer(int source, SurfaceGrid& deposit) {
    const int n = mGrid.slicesPerLayer, L = mLayersInFlight, M = int(mStencils.size());
    const auto start = std::chrono::steady_clock::now();
    const std::vector<RowExtent> extents = rowExtents(deposit);
    // (stencil, slot): slice s of each layer k still receiving takes stencil (source - k) n + s.
    std::vector<std::pair<int, int>> pairs;
    for (int k = source; k >= 0 && k > source - L; --k)
        for (int s = 0; s < n; ++s)
            if ((source - k) * n + s < M) pairs.push_back({(source - k) * n + s, (k % L) * n + s});
    if (mGpu) {
        // Every layer above has been added: with this one, its slices are final.
        std::vector<int> finished;
        for (int s = 0; s < n; ++s) finished.push_back((source % L) * n + s);
        return mGpu->addLayer(deposit, extents, pairs, finished);
    }
    std::vector<GatherTarget> targets;
    for (const auto& [m, slot] : pairs)
        targets.push_back({&mCpu->taps[size_t(m)], mAccumulators[size_t(slot)].values.data()});
    padDeposit(deposit, reachCells(), mCpu->padded);
    gatherGrids(mCpu->padded, extents, reachCells(), targets);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void TabulatedExposureEngine::emitLayer(int source, double top, const SliceSink& sink) {
    // Every layer above `source` has been added, so its slices are final.
    const int n = mGrid.slicesPerLayer, L = mLayersInFlight;
    const double dz = mLayerThickness / n;
    for (int s = 0; s < n; ++s) {
        const int slot = (source % L) * n + s;
        if (mGpu) {
            mGpu->takeSlot(slot, mAccumulators.front());
            sink({source, s, top - (s + 0.5) * dz, &mAccumulators.front()});
            continue;
        }
        SurfaceGrid& slice = mAccumulators[size_t(slot)];
        sink({source, s, top - (s + 0.5) * dz, &slice});
        // The slot serves layer source - L next.
        std::fill(slice.values.begin(), slice.values.end(), 0.0f);
    }
}

int TabulatedExposureEngine::reachCells() const {
    int reach = 0;
    for (const DepthStencil& st : mStencils) reach = std::max(reach, st.halfWidth);
    return reach;
}

int TabulatedExposureEngine::shaderStencilsPerInvocation() const {
    return mGpu ? mGpu->perInvocation : 0;
}

int TabulatedExposureEngine::stencilIndexAt(double depth) const {
    if (!(depth >= 0)) throw InputError("exposure depth must be >= 0");
    int m = int(std::floor(depth * mGrid.slicesPerLayer / mLayerThickness));
    return m < int(mStencils.size()) ? m : -1;
}

namespace {

/// out(i, j) += sum w(di, dj) in(i + di, j + dj), through the CPU gather (in's rows folded about
/// each output row). The stencils are symmetric (w(-di, -dj) = w(di, dj) bit for bit), so this
/// is the map's adjoint as well.
void applyStencil(const StencilTaps& taps, const SurfaceGrid& in, SurfaceGrid& out) {
    PaddedDeposit padded;
    padDeposit(in, taps.halfWidth, padded);
    gatherGrids(padded, rowExtents(in), taps.halfWidth, {{&taps, out.values.data()}});
}

}  // namespace

SurfaceGrid TabulatedExposureEngine::layerMap(const SurfaceGrid& deposit, double depth) {
    SurfaceGrid out = mGrid.surface();
    int m = stencilIndexAt(depth);
    if (m >= 0) applyStencil(mCpu->taps[size_t(m)], deposit, out);
    return out;
}

SurfaceGrid TabulatedExposureEngine::layerMapAdjoint(const SurfaceGrid& map, double depth) {
    SurfaceGrid out = mGrid.surface();
    int m = stencilIndexAt(depth);
    if (m >= 0) applyStencil(mCpu->taps[size_t(m)], map, out);
    return out;
}

std::vector<SurfaceGrid> TabulatedExposureEngine::stackAdjoint(const ExposureField& field) {
    const int layers = fieldLayers(field, mGrid);
    const int n = mGrid.slicesPerLayer, M = int(mStencils.size());
    std::vector<SurfaceGrid> deposits(layers, mGrid.surface());
    for (int source = 0; source < layers; ++source)
        for (int k = source; k >= 0 && (source - k) * n < M; --k)
            for (int s = 0; s < n && (source - k) * n + s < M; ++s)
                applyStencil(mCpu->taps[size_t((source - k) * n + s)], field[size_t(k) * n + s],
                             deposits[source]);
    return deposits;
}

}  // namespace vpsim::exposure
