#include "exposure/stencil_gather.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "exposure/avx2_clones.h"

namespace vpsim::exposure {
namespace {

constexpr int BLOCK = 8;  ///< outputs summed at once: one AVX2 register

/// 8 floats as one vector (GCC/Clang vector extension: two SSE registers in the baseline build,
/// one AVX2 register in the AVX2 clone); the loop over 8 lanes was not vectorised.
typedef float Float8 __attribute__((vector_size(BLOCK * sizeof(float))));

/// One source row's part in an output row's gather: the padded source row, the stencil row's
/// taps, and the outputs [lo, hi] that any of its taps reaches from the row's non-zero cells.
struct SourceRow {
    const float* src;
    const int* offset;
    const float* weight;
    int taps, lo, hi;
};

/// out[i] for i in [lo, hi]: its terms from every row in order, each row's taps in order. Four
/// blocks at a time, so that four chains of adds (one per block, as each output's order requires)
/// overlap; then single blocks; then single cells.
VPSIM_AVX2_CLONES void gatherBlocks(float* __restrict out, int lo, int hi, int nx,
                                    const SourceRow* rows, int count) {
    constexpr int WIDE = 4 * BLOCK;
    int i = lo / BLOCK * BLOCK;
    for (; i + WIDE <= nx && i <= hi; i += WIDE) {
        Float8 s0, s1, s2, s3, c0, c1, c2, c3;  // unaligned loads and stores through memcpy
        std::memcpy(&s0, out + i, sizeof s0);
        std::memcpy(&s1, out + i + BLOCK, sizeof s1);
        std::memcpy(&s2, out + i + 2 * BLOCK, sizeof s2);
        std::memcpy(&s3, out + i + 3 * BLOCK, sizeof s3);
        for (int r = 0; r < count; ++r) {
            const SourceRow& row = rows[r];
            if (i + WIDE - 1 < row.lo || i > row.hi) continue;  // only zero terms
            for (int t = 0; t < row.taps; ++t) {
                const float* cell = row.src + i + row.offset[t];
                std::memcpy(&c0, cell, sizeof c0);
                std::memcpy(&c1, cell + BLOCK, sizeof c1);
                std::memcpy(&c2, cell + 2 * BLOCK, sizeof c2);
                std::memcpy(&c3, cell + 3 * BLOCK, sizeof c3);
                const float w = row.weight[t];
                s0 += w * c0;
                s1 += w * c1;
                s2 += w * c2;
                s3 += w * c3;
            }
        }
        std::memcpy(out + i, &s0, sizeof s0);
        std::memcpy(out + i + BLOCK, &s1, sizeof s1);
        std::memcpy(out + i + 2 * BLOCK, &s2, sizeof s2);
        std::memcpy(out + i + 3 * BLOCK, &s3, sizeof s3);
    }
    for (; i + BLOCK <= nx && i <= hi; i += BLOCK) {
        Float8 sum, cells;
        std::memcpy(&sum, out + i, sizeof sum);
        for (int r = 0; r < count; ++r) {
            const SourceRow& row = rows[r];
            if (i + BLOCK - 1 < row.lo || i > row.hi) continue;
            for (int t = 0; t < row.taps; ++t) {
                std::memcpy(&cells, row.src + i + row.offset[t], sizeof cells);
                sum += row.weight[t] * cells;
            }
        }
        std::memcpy(out + i, &sum, sizeof sum);
    }
    for (; i <= hi; ++i) {  // the row's last cells, fewer than a block
        float sum = out[i];
        for (int r = 0; r < count; ++r)
            for (int t = 0; t < rows[r].taps; ++t)
                sum += rows[r].weight[t] * rows[r].src[i + rows[r].offset[t]];
        out[i] = sum;
    }
}

}  // namespace

StencilTaps stencilTaps(const DepthStencil& stencil) {
    StencilTaps taps;
    const int H = stencil.halfWidth;
    taps.halfWidth = H;
    taps.rowStart.push_back(0);
    for (int dj = 0; dj <= H; ++dj) {
        const int hw = stencil.rowHalfWidth[size_t(dj + H)];
        if (hw != stencil.rowHalfWidth[size_t(H - dj)])
            throw std::logic_error("stencilTaps: the stencil is not mirror symmetric");
        for (int di = -hw; di <= hw; ++di) {
            const float w = stencil.at(di, dj);
            if (w != stencil.at(di, -dj) || w != stencil.at(-di, dj))
                throw std::logic_error("stencilTaps: the stencil is not mirror symmetric");
            if (w == 0.0f) continue;
            taps.offset.push_back(di);
            taps.weight.push_back(w);
        }
        taps.rowStart.push_back(int(taps.offset.size()));
    }
    return taps;
}

void padDeposit(const SurfaceGrid& deposit, int padding, PaddedDeposit& padded) {
    padded.nx = deposit.nx;
    padded.ny = deposit.ny;
    padded.padding = padding;
    padded.values.assign(size_t(deposit.nx + 2 * padding) * deposit.ny, 0.0f);
    for (int j = 0; j < deposit.ny; ++j)
        std::memcpy(padded.row(j), deposit.values.data() + size_t(j) * deposit.nx,
                    size_t(deposit.nx) * sizeof(float));
}

void FoldedRows::fold(const PaddedDeposit& deposit, const std::vector<RowExtent>& extents, int j,
                      int reach) {
    if (mNx != deposit.nx || mPadding != deposit.padding || mReach != reach) {
        mNx = deposit.nx;
        mPadding = deposit.padding;
        mReach = reach;
        mWidth = mNx + 2 * mPadding;
        mValues.assign(size_t(reach) * size_t(mWidth), 0.0f);
        mExtents.assign(size_t(reach) + 1, RowExtent{0, -1});
        mWritten.assign(size_t(reach) + 1, RowExtent{0, -1});
    }
    const auto present = [&](int sj) {
        return sj >= 0 && sj < deposit.ny && extents[size_t(sj)].first <= extents[size_t(sj)].last;
    };
    mCentre = deposit.row(j);
    mExtents[0] = present(j) ? extents[size_t(j)] : RowExtent{0, -1};
    for (int d = 1; d <= reach; ++d) {
        float* out = mValues.data() + offset(d);
        const RowExtent written = mWritten[size_t(d)];
        if (written.first <= written.last)
            std::fill(out + written.first, out + written.last + 1, 0.0f);
        const bool up = present(j + d), down = present(j - d);
        RowExtent e{0, -1};
        if (up) e = extents[size_t(j + d)];
        if (down)
            e = up ? RowExtent{std::min(e.first, extents[size_t(j - d)].first),
                               std::max(e.last, extents[size_t(j - d)].last)}
                   : extents[size_t(j - d)];
        if (up && down) {
            const float *a = deposit.row(j + d), *b = deposit.row(j - d);
            for (int i = e.first; i <= e.last; ++i) out[i] = a[i] + b[i];
        } else if (up || down) {
            const float* a = deposit.row(up ? j + d : j - d);
            std::copy(a + e.first, a + e.last + 1, out + e.first);
        }
        mExtents[size_t(d)] = e;
        mWritten[size_t(d)] = e;
    }
}

const float* FoldedRows::row(int d) const {
    return d == 0 ? mCentre : mValues.data() + offset(d);
}

void gatherRow(float* out, const StencilTaps& taps, const FoldedRows& rows) {
    const int H = taps.halfWidth, nx = rows.nx();
    thread_local std::vector<SourceRow> list;  // reused: one per stencil row
    list.resize(size_t(H + 1));
    int count = 0, lo = nx, hi = -1;
    for (int d = 0; d <= H && d <= rows.reach(); ++d) {
        const int first = taps.rowStart[size_t(d)], end = taps.rowStart[size_t(d + 1)];
        const RowExtent& extent = rows.extent(d);
        if (first == end || extent.first > extent.last) continue;
        // Output i gathers cell i + di: the row's non-zero cells reach outputs
        // [extent.first - largest di, extent.last - smallest di].
        SourceRow& row = list[count++];
        row = {rows.row(d),
               &taps.offset[size_t(first)],
               &taps.weight[size_t(first)],
               end - first,
               std::max(0, extent.first - taps.offset[size_t(end - 1)]),
               std::min(nx - 1, extent.last - taps.offset[size_t(first)])};
        lo = std::min(lo, row.lo);
        hi = std::max(hi, row.hi);
    }
    if (count > 0 && lo <= hi) gatherBlocks(out, lo, hi, nx, list.data(), count);
}

void gatherGrids(const PaddedDeposit& deposit, const std::vector<RowExtent>& extents, int reach,
                 const std::vector<GatherTarget>& targets) {
    const size_t nx = size_t(deposit.nx);
    // Each output row is written by one task.
    tbb::parallel_for(tbb::blocked_range<int>(0, deposit.ny),
                      [&](const tbb::blocked_range<int>& rows) {
                          thread_local FoldedRows folded;
                          for (int j = rows.begin(); j < rows.end(); ++j) {
                              folded.fold(deposit, extents, j, reach);
                              for (const GatherTarget& t : targets)
                                  gatherRow(t.values + size_t(j) * nx, *t.taps, folded);
                          }
                      });
}

}  // namespace vpsim::exposure
