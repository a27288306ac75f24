#pragma once
// Private: the tabulated engine's CPU gather, out(i, j) += sum w(di, dj) S(i + di, j + dj), one
// output row at a time. Each output is loaded and stored once per stencil, 32 at a time, and gets
// its terms in the order of one axpy per tap (rows dj ascending, taps di ascending, zero weights
// skipped): the same sums bit for bit, since the terms it adds beyond a tap's axpy range are
// products with zero deposit (+0: weights and deposits are never negative).
#include <vector>

#include "exposure/row_extents.h"
#include "vpsim/exposure/tabulated_engine.h"

namespace vpsim::exposure {

/// A stencil's non-zero taps, row by row: row dj + halfWidth holds taps rowStart[dj + halfWidth]
/// up to rowStart[dj + halfWidth + 1], in ascending di.
struct StencilTaps {
    int halfWidth = 0;
    std::vector<int> rowStart;
    std::vector<int> offset;  ///< di
    std::vector<float> weight;
};

StencilTaps stencilTaps(const DepthStencil& stencil);

/// A deposit copied with halfWidth zero cells on each side of every row, so that a gather reads
/// any cell i + di of a row without a bounds test.
struct PaddedDeposit {
    int nx = 0, ny = 0, padding = 0;
    std::vector<float> values;
    /// Row sj, indexed by the deposit's column (from -padding to nx - 1 + padding).
    const float* row(int sj) const { return values.data() + offset(sj); }
    float* row(int sj) { return values.data() + offset(sj); }
    size_t offset(int sj) const { return size_t(sj) * size_t(nx + 2 * padding) + size_t(padding); }
};

/// Copies `deposit` into `padded` (reusing its storage), with `padding` zeros on each side.
void padDeposit(const SurfaceGrid& deposit, int padding, PaddedDeposit& padded);

/// Adds stencil `taps` gathered from `deposit` (its rows' non-zero extents given) to output row j,
/// `out` (nx cells).
void gatherRow(float* out, int j, const StencilTaps& taps, const PaddedDeposit& deposit,
               const std::vector<RowExtent>& extents);

}  // namespace vpsim::exposure
