#pragma once
/// @file
/// The pictures of a run: exposure cross-sections, deviation maps, XY error per layer.
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include "vpsim/cure/cure_law.h"
#include "vpsim/exposure/exposure_model.h"

#include "vpsim/geometry/mesh.h"
#include "vpsim/geometry/polygons.h"
#include "vpsim/validate/slice_validator.h"

namespace vpsim::report {

/// Records an x-z cross-section along grid row `row` and an x-y map of one layer while the engine
/// runs (a SliceSink), and draws them with the reference outline (red) and the cured outline at
/// the cure law's critical dose (white), exposure from 0 (dark) to the largest value (yellow).
class SectionRecorder {
public:
    SectionRecorder(const geometry::Mesh& part, const exposure::ExposureGrid& grid, int totalSlices,
                    const cure::CureLaw& law, int mapLayer, int row);
    void add(const exposure::ExposureSlice& slice);
    /// Writes exposure_xz.png and exposure_xy.png into `directory`.
    void write(const std::string& directory) const;

private:
    const geometry::Mesh& mPart;
    exposure::ExposureGrid mGrid;
    const cure::CureLaw& mLaw;
    int mMapLayer, mRow, mTotalSlices, mFilled = 0;
    std::vector<float> mSection;          ///< [slice from the top][x]
    std::vector<uint8_t> mSectionInside;  ///< reference at the same cells
    std::vector<float> mMap;              ///< x-y exposure of mMapLayer's middle slice
    std::vector<uint8_t> mMapInside;
};

/// The grid row crossing most of `region` (where an x-z section shows the most of the part).
int busiestRow(const geometry::PolygonSet& region, const exposure::ExposureGrid& grid);

/// Histogram of signed surface deviations (SVG) and a top view of the cured surface coloured by
/// deviation (PNG, blue inside the model, red outside).
void writeDeviationFigures(const std::string& directory, const std::vector<glm::vec3>& cured,
                           const std::vector<float>& deviations);
/// Per-layer XY contour error against height (SVG).
void writeLayerErrorPlot(const std::string& path, const validate::SliceValidationSummary& summary);

}  // namespace vpsim::report
