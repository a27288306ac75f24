#include <catch2/catch.hpp>

#include <random>

#include "exposure/row_extents.h"
#include "exposure/stencil_gather.h"

using namespace vpsim;
using namespace vpsim::exposure;

namespace {

/// A stencil of half-width H with random weights in a disc, zeros scattered among them, mirror
/// symmetric in di and dj (as the engine's radial stencils are); `broken` breaks it in dj (1) or
/// di (2).
DepthStencil randomStencil(int H, std::mt19937& rng, int broken = 0) {
    std::uniform_real_distribution<float> weight(0.0f, 1.0f);
    DepthStencil st;
    st.halfWidth = H;
    st.weights.assign(size_t(2 * H + 1) * (2 * H + 1), 0.0f);
    st.rowHalfWidth.assign(size_t(2 * H + 1), -1);
    for (int dj = 0; dj <= H; ++dj)
        for (int di = 0; di <= H; ++di)
            if (di * di + dj * dj <= H * H && weight(rng) > 0.2f) {
                const float w = weight(rng);
                for (int row : {H + dj, H - dj}) {
                    for (int column : {H + di, H - di})
                        st.weights[size_t(row) * (2 * H + 1) + size_t(column)] = w;
                    st.rowHalfWidth[size_t(row)] = std::max(st.rowHalfWidth[size_t(row)], di);
                }
            }
    if (broken == 1) st.weights[size_t(H + 1) * (2 * H + 1) + size_t(H)] += 0.5f;
    if (broken == 2) st.weights[size_t(H) * (2 * H + 1) + size_t(H + 1)] += 0.5f;
    return st;
}

}  // namespace

// The folded gather (rows j + d and j - d added first) against the direct sum over every tap in
// double precision: equal to float rounding, 4e-6 of the sum of the terms' magnitudes (a float
// sum of n terms errs by at most about n x 6e-8 of it, typically sqrt(n) x 6e-8: 1e-6 here).
// Sparse random deposits (empty rows, rows with a few cells, full rows), widths that leave
// partial blocks, and stencils wider than the grid. One fold serves two stencils of different
// widths, as it serves every depth stencil in the engine.
TEST_CASE("the folded stencil gather equals the direct sum", "[exposure]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(0.0f, 3.0f);
    std::uniform_int_distribution<int> kind(0, 3);
    for (const auto& [nx, ny, H] : {std::tuple{37, 23, 5}, std::tuple{100, 41, 12},
                                    std::tuple{8, 9, 11}, std::tuple{131, 17, 2}}) {
        const std::vector<DepthStencil> stencils{randomStencil(H, rng),
                                                 randomStencil(std::max(1, H / 2), rng)};
        SurfaceGrid deposit(nx, ny, 0.0, 0.0, 0.01);
        for (int j = 0; j < ny; ++j) {
            const int k = kind(rng);
            for (int i = 0; i < nx; ++i) {
                const bool on = k == 3 || (k == 2 && (i * 7 + j) % 11 == 0);
                deposit.values[size_t(j) * nx + i] = on ? value(rng) : 0.0f;
            }
        }
        const std::vector<RowExtent> extents = rowExtents(deposit);
        PaddedDeposit padded;
        padDeposit(deposit, H, padded);
        FoldedRows folded;
        for (const DepthStencil& st : stencils) {
            const int h = st.halfWidth;
            // Outputs start from non-zero sums, as a slice receiving its second layer does.
            std::vector<float> start(size_t(nx) * ny);
            for (float& v : start) v = value(rng);
            std::vector<float> gathered = start;
            const StencilTaps taps = stencilTaps(st);
            for (int j = 0; j < ny; ++j) {
                folded.fold(padded, extents, j, H);
                gatherRow(gathered.data() + size_t(j) * nx, taps, folded);
            }
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i) {
                    double sum = start[size_t(j) * nx + i], magnitude = std::abs(sum);
                    for (int dj = -h; dj <= h; ++dj)
                        for (int di = -h; di <= h; ++di) {
                            const int si = i + di, sj = j + dj;
                            if (si < 0 || si >= nx || sj < 0 || sj >= ny) continue;
                            const double term =
                                double(st.at(di, dj)) * deposit.values[size_t(sj) * nx + si];
                            sum += term;
                            magnitude += std::abs(term);
                        }
                    REQUIRE(gathered[size_t(j) * nx + i] ==
                            Approx(sum).margin(4e-6 * magnitude).epsilon(0));
                }
        }
    }
}

TEST_CASE("the folded gather refuses a stencil that is not mirror symmetric", "[exposure]") {
    std::mt19937 rng(3);
    CHECK_NOTHROW(stencilTaps(randomStencil(4, rng)));
    CHECK_THROWS_AS(stencilTaps(randomStencil(4, rng, 1)), std::logic_error);
    CHECK_THROWS_AS(stencilTaps(randomStencil(4, rng, 2)), std::logic_error);
}
