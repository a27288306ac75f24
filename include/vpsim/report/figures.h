#pragma once
/// @file
/// The pictures of a run: exposure cross-sections, deviation maps, XY error per layer.
#include <string>
#include <vector>

#include "vpsim/core/binary_state.h"
#include "vpsim/cure/cure_law.h"
#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/geometry/polygons.h"
#include "vpsim/validate/slice_validator.h"

namespace vpsim::report {

/// Records an x-z cross-section along grid row `row` and an x-y map of one layer while the engine
/// runs (a SliceSink), and draws them through the plotting layer (plot.h): mm axes at the true
/// aspect ratio, exposure in mJ/cm^2 with its colour bar, the model's outline (red) and the cured
/// outline at the cure law's critical dose (white) in a legend, a scale bar.
class SectionRecorder {
public:
    SectionRecorder(const geometry::Mesh& part, const exposure::ExposureGrid& grid, int totalSlices,
                    const cure::CureLaw& law, int mapLayer, int row);
    void add(const exposure::ExposureSlice& slice);
    /// Writes exposure_xz and exposure_xy (.svg and .png) into `directory`.
    void write(const std::string& directory) const;
    /// Checkpoints, between two tiles: what is recorded so far, as records named "sections.*".
    /// @throw InputError naming the state file when it is malformed or of another grid
    void saveState(BinaryStateWriter& out) const;
    void restoreState(const BinaryStateReader& in);
    /// An MPI rank's tile, recorded alone: what it recorded of the tile's `core` cells (records
    /// "sections.tile_*"); mergePartial copies them into this recorder's pictures.
    /// @throw InputError naming the state file when it is malformed
    void savePartial(BinaryStateWriter& out, const exposure::CellWindow& core) const;
    void mergePartial(const BinaryStateReader& in, const exposure::CellWindow& core);

private:
    const geometry::Mesh& mPart;
    exposure::ExposureGrid mGrid;
    const cure::CureLaw& mLaw;
    int mMapLayer, mRow, mTotalSlices, mFilled = 0;
    double mTopZ = 0, mBottomZ = 0;       ///< mm, centres of the first and last recorded slices
    std::vector<float> mSection;          ///< [slice from the top][x]
    std::vector<uint8_t> mSectionInside;  ///< reference at the same cells
    std::vector<float> mMap;              ///< x-y exposure of mMapLayer's middle slice
    std::vector<uint8_t> mMapInside;
};

/// The grid row crossing the most material of all layers' `regions` together (where an x-z
/// section shows the most of the part).
int busiestRow(const std::vector<geometry::PolygonSet>& regions,
               const exposure::ExposureGrid& grid);

/// Per-layer XY contour error against height: `stem`.svg and `stem`.png.
void writeLayerErrorPlot(const std::string& stem, const validate::SliceValidationSummary& summary);

}  // namespace vpsim::report
