#pragma once
/// @file
/// The 3D view's per-layer x-y sections and kernel map: a slice sink that keeps, for each layer,
/// the exposure of its middle voxel slice downsampled to at most SECTION_MAX_SIDE pixels on its
/// long side (with the cured share of each pixel), and writes them with the layers' model
/// outlines, and the Monte Carlo kernel I(r, z) with its Eq. 12 fit, to sections.js beside
/// index.html (base64 in a classic script, like mesh3d.js: Chromium blocks fetch() on file://).
/// The run never stores the 3D grid: the kept pixels are bounded by SECTION_PIXEL_BUDGET, first
/// by coarser pixels (down to SECTION_MIN_SIDE), then by keeping every n-th layer.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vpsim/core/binary_state.h"
#include "vpsim/cure/cure_law.h"
#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/kernel/beam_kernel.h"
#include "vpsim/report/job_result.h"

namespace vpsim::report {

/// Pixels on the long side of a section at most, and the fewest before layers are skipped.
constexpr int SECTION_MAX_SIDE = 256;
constexpr int SECTION_MIN_SIDE = 64;
/// Section pixels kept over all layers: 4 M (20 MB while the run streams, 1.5 B per pixel of
/// sections.js: uint8 exposure and a cured bit, base64), well inside REPORT_SIZE_TARGET.
constexpr uint64_t SECTION_PIXEL_BUDGET = 4ull << 20;

/// How the sections sample the exposure grid: `factor` x `factor` cells per pixel, every
/// `stride`-th layer from the bottom (and the top layer).
struct SectionSampling {
    int factor = 1, width = 0, height = 0, stride = 1;
};

/// The sampling of `layers` layers of an nx x ny cell grid under the limits above.
SectionSampling sectionSampling(int nx, int ny, int layers);

/// Bytes the recorder holds while the run streams (for the job's estimate).
uint64_t layerSectionBytes(int nx, int ny, int layers);

class LayerSectionRecorder {
public:
    LayerSectionRecorder(const geometry::LayerStack& stack, const exposure::ExposureGrid& grid,
                         const cure::CureLaw& law);
    /// A SliceSink: keeps the middle slice of each kept layer.
    void add(const exposure::ExposureSlice& slice);
    /// Writes sections.js and its viewer section_view.js into `outDir`: the sections on one linear
    /// mJ/cm^2 scale (0 to the 99th percentile of the kept pixels, at least twice the critical
    /// dose), the cured pixels (at least half of their cells at or above the critical dose), the
    /// layers' outlines, and `kernel`'s I(r, z) and fit when given.
    /// @throw InputError when the file cannot be written
    SectionViewSummary write(const std::string& outDir, const kernel::BeamKernel* kernel) const;
    /// Checkpoints, between two tiles: the sums so far, as records named "layer_sections.*".
    /// @throw InputError naming the state file when it is malformed or of another grid
    void saveState(BinaryStateWriter& out) const;
    void restoreState(const BinaryStateReader& in);
    /// An MPI rank's tile, recorded alone: the sums of the pixels over the tile's `core` cells
    /// (records "layer_sections.tile_*"). mergePartial adds them to this recorder's, as one
    /// process does after each slice (add sums a slice's share of a pixel apart, from zero): the
    /// same sums to the bit. @throw InputError naming the state file when it is malformed
    void savePartial(BinaryStateWriter& out, const exposure::CellWindow& core) const;
    void mergePartial(const BinaryStateReader& in, const exposure::CellWindow& core);

private:
    const geometry::LayerStack& mStack;
    exposure::ExposureGrid mGrid;
    const cure::CureLaw& mLaw;
    SectionSampling mSampling;
    std::vector<int> mSlot;        ///< per layer: its index among the kept ones, or -1
    std::vector<int> mKept;        ///< kept layer indices, bottom first
    std::vector<double> mZ;        ///< mm, height of each kept layer's recorded slice
    std::vector<float> mExposure;  ///< [kept][row from y0][column]: sum over the block, mJ/mm^2
    std::vector<uint32_t> mCured;  ///< same pixels: cured cells of the block
    /// Cells of each pixel's block (edge blocks are cut by the grid), per layer.
    std::vector<float> blockCells() const;
    /// The pixels holding cells of `core`: [x0, x1) x [y0, y1).
    std::array<int, 4> pixelWindow(const exposure::CellWindow& core) const;
};

}  // namespace vpsim::report
