#pragma once
/// @file
/// Streaming comparison of the cured part with the reference model, slice by slice, while the
/// exposure engine produces the slices (so no full 3D grid is needed): each voxel slice is cured
/// at the critical dose and compared with the part's cross-section at the slice's height,
/// rasterised on the same grid (pixel centres inside).
///
/// Gives the volume IoU, per-layer XY contour error (area of the symmetric difference divided by
/// the reference perimeter: the mean distance between cured and reference contours), and the
/// over-cure below down-facing surfaces (the depth of cured resin directly beneath the reference
/// solid, along each column where the reference ends going down, i.e. print-through).

#include <memory>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/cure/cure_law.h"
#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/mesh.h"

namespace vpsim::validate {

/// One layer's mid-plane comparison.
struct LayerComparison {
    int layer = 0;
    double z = 0;                   ///< mm
    double referenceArea = 0;       ///< mm^2
    double curedArea = 0;           ///< mm^2
    double intersectionArea = 0;    ///< mm^2
    double referencePerimeter = 0;  ///< mm
    /// (cured XOR reference area) / reference perimeter, mm; 0 when the layer has no reference.
    double xyContourError() const;
};

struct SliceValidationSummary {
    double iou = 0;              ///< |cured AND reference| / |cured OR reference| (volume)
    double curedVolume = 0;      ///< mm^3
    double referenceVolume = 0;  ///< mm^3 (of the voxelised reference)
    /// Over-cure below down-facing surfaces (mm) over the columns where the reference ends going
    /// down. The median is the robust figure: columns beside a vertical wall carry the wall's
    /// lateral over-cure all the way down and dominate the max.
    double overcureBelowDownFacingMedian = 0;
    double overcureBelowDownFacingMax = 0;
    double overcureBelowDownFacingMean = 0;
    long downFacingColumns = 0;
    double maxDose = 0;             ///< largest exposure of any voxel (mJ/mm^2)
    uint64_t exposedVoxels = 0;     ///< voxels above 2% of Ec (what a .vdb of the exposure stores)
    double xyContourErrorMean = 0;  ///< mm, mean over layers with reference area
    double xyContourErrorMax = 0;   ///< mm
    std::vector<LayerComparison> layers;  ///< bottom layer first
    nlohmann::json toJson() const;
};

class SliceValidator {
public:
    /// @param law decides which voxels are cured (kept by reference: it must outlive the validator)
    /// @param voxelHeight  height of one voxel slice (mm)
    SliceValidator(const geometry::Mesh& part, const exposure::ExposureGrid& grid,
                   const cure::CureLaw& law, double voxelHeight);
    ~SliceValidator();
    /// A SliceSink. Slices must arrive from the top down (the engine's order).
    void add(const exposure::ExposureSlice& slice);
    SliceValidationSummary summary() const;
    /// Between two tiles: what the next tiles build on (counts, finished runs, per-layer counts),
    /// for a checkpoint; restoreState continues from it. @throw InputError for a malformed state
    nlohmann::json saveState();
    void restoreState(const nlohmann::json& state);
    /// Adds the state of a validator that saw later tiles (MPI ranks' tiles, in the tiles'
    /// order): counts add, runs append, the maximum is the larger.
    void mergeState(const nlohmann::json& later);

private:
    struct State;
    std::unique_ptr<State> mState;
};

}  // namespace vpsim::validate
