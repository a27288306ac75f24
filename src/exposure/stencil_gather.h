#pragma once
// Private: the tabulated engine's CPU gather, out(i, j) += sum w(di, dj) S(i + di, j + dj), one
// output row at a time. The stencils are symmetric in dj (the kernel is radial), so the deposit
// rows j + d and j - d are added first (FoldedRows, once per output row for every stencil) and
// each stencil row pair is gathered once: half the multiply-adds of a gather over all 2H + 1
// rows. Each output is loaded and stored once per stencil, 32 at a time, and gets its terms in
// a fixed order (folded rows d ascending, taps di ascending, zero weights skipped), the same
// whatever the grid around it, so tiled and untiled runs sum alike.
#include <vector>

#include "exposure/row_extents.h"
#include "vpsim/exposure/tabulated_engine.h"

namespace vpsim::exposure {

/// A stencil's non-zero taps on its rows dj = 0..halfWidth (row -dj holds the same): row dj
/// holds taps rowStart[dj] up to rowStart[dj + 1], in ascending di.
struct StencilTaps {
    int halfWidth = 0;
    std::vector<int> rowStart;
    std::vector<int> offset;  ///< di
    std::vector<float> weight;
};

/// @throw std::logic_error when the stencil is not mirror symmetric (w(di, dj) = w(-di, dj) =
/// w(di, -dj)) bit for bit: the gather folds rows dj and -dj, and the engine takes the gather as
/// its own adjoint
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

/// A deposit's rows folded about output row j: row d (0..reach) holds S(j + d) + S(j - d) (row 0:
/// S(j)), rows outside the grid counted as zero, readable from column -padding to
/// nx - 1 + padding and zero outside its non-zero columns, extent(d). Reused from row to row:
/// each fold clears only what the one before it wrote.
class FoldedRows {
public:
    /// Folds `deposit` (its rows' non-zero extents given) about row j, `reach` rows each side
    /// (at most the deposit's padding).
    void fold(const PaddedDeposit& deposit, const std::vector<RowExtent>& extents, int j,
              int reach);
    /// Row d, indexed by the deposit's column.
    const float* row(int d) const;
    const RowExtent& extent(int d) const { return mExtents[size_t(d)]; }
    int nx() const { return mNx; }
    int reach() const { return mReach; }

private:
    /// Where row d >= 1 starts in mValues (its column 0).
    size_t offset(int d) const { return size_t(d - 1) * size_t(mWidth) + size_t(mPadding); }
    int mNx = 0, mPadding = 0, mReach = 0, mWidth = 0;
    const float* mCentre = nullptr;   ///< row 0: the deposit's row j itself
    std::vector<float> mValues;       ///< rows 1..reach, padded like the deposit
    std::vector<RowExtent> mExtents;  ///< per row d, its non-zero columns
    std::vector<RowExtent> mWritten;  ///< per row d >= 1, the columns the last fold wrote
};

/// Adds stencil `taps` gathered from the deposit folded about output row j to that row, `out`
/// (nx cells).
void gatherRow(float* out, const StencilTaps& taps, const FoldedRows& rows);

/// A stencil and the grid (the deposit's nx x ny cells) that its gather adds to.
struct GatherTarget {
    const StencilTaps* taps;
    float* values;
};

/// Adds each target's stencil gathered from `deposit` (its rows' non-zero extents given) to the
/// target's grid: TBB-parallel over output rows, each row's deposit folded once for every target,
/// `reach` rows each side (the widest target's half-width, at most the deposit's padding).
void gatherGrids(const PaddedDeposit& deposit, const std::vector<RowExtent>& extents, int reach,
                 const std::vector<GatherTarget>& targets);

}  // namespace vpsim::exposure
