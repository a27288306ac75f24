#include <catch2/catch.hpp>

#include <random>

#include "exposure/row_extents.h"
#include "exposure/stencil_gather.h"

using namespace vpsim;
using namespace vpsim::exposure;

namespace {

/// A stencil of half-width H with random weights in a disc, zeros scattered among them.
DepthStencil randomStencil(int H, std::mt19937& rng) {
    std::uniform_real_distribution<float> weight(0.0f, 1.0f);
    DepthStencil st;
    st.halfWidth = H;
    st.weights.assign(size_t(2 * H + 1) * (2 * H + 1), 0.0f);
    for (int dj = -H; dj <= H; ++dj) {
        int hw = -1;
        for (int di = -H; di <= H; ++di)
            if (di * di + dj * dj <= H * H && weight(rng) > 0.2f) {
                st.weights[size_t(dj + H) * (2 * H + 1) + size_t(di + H)] = weight(rng);
                hw = std::max(hw, std::abs(di));
            }
        st.rowHalfWidth.push_back(hw);
    }
    return st;
}

}  // namespace

// The blocked gather must give the sums of the per-tap axpy it replaced bit for bit: the same
// terms in the same order (rows dj ascending, taps di ascending, zero weights skipped), over
// each deposit row's non-zero columns. Sparse random deposits (empty rows, rows with a few
// cells, full rows), widths that leave partial blocks, and stencils wider than the grid.
TEST_CASE("the blocked stencil gather equals the per-tap axpy bit for bit", "[exposure]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(0.0f, 3.0f);
    std::uniform_int_distribution<int> kind(0, 3);
    for (const auto& [nx, ny, H] : {std::tuple{37, 23, 5}, std::tuple{100, 41, 12},
                                    std::tuple{8, 9, 11}, std::tuple{131, 17, 2}}) {
        const DepthStencil st = randomStencil(H, rng);
        SurfaceGrid deposit(nx, ny, 0.0, 0.0, 0.01);
        for (int j = 0; j < ny; ++j) {
            const int k = kind(rng);
            for (int i = 0; i < nx; ++i) {
                const bool on = k == 3 || (k == 2 && (i * 7 + j) % 11 == 0);
                deposit.values[size_t(j) * nx + i] = on ? value(rng) : 0.0f;
            }
        }
        const std::vector<RowExtent> extents = rowExtents(deposit);
        // Outputs start from non-zero sums, as a slice receiving its second layer does.
        std::vector<float> start(size_t(nx) * ny);
        for (float& v : start) v = value(rng);
        std::vector<float> reference = start, blocked = start;
        for (int j = 0; j < ny; ++j)
            for (int dj = -H; dj <= H; ++dj) {
                const int sj = j + dj, hw = st.rowHalfWidth[size_t(dj + H)];
                if (sj < 0 || sj >= ny || hw < 0 || extents[sj].first > extents[sj].last) continue;
                for (int di = -hw; di <= hw; ++di) {
                    const float w = st.at(di, dj);
                    if (w == 0.0f) continue;
                    const int lo = std::max(0, extents[sj].first - di);
                    const int hi = std::min(nx - 1, extents[sj].last - di);
                    for (int i = lo; i <= hi; ++i)
                        reference[size_t(j) * nx + i] +=
                            w * deposit.values[size_t(sj) * nx + i + di];
                }
            }
        const StencilTaps taps = stencilTaps(st);
        PaddedDeposit padded;
        padDeposit(deposit, H, padded);
        for (int j = 0; j < ny; ++j)
            gatherRow(blocked.data() + size_t(j) * nx, j, taps, padded, extents);
        CHECK(blocked == reference);
    }
}
