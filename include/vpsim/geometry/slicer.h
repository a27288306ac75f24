#pragma once
/// @file
/// Slicing a closed, consistently oriented mesh into layers of polygons with holes.
///
/// Layer k covers z in [z0 + k t, z0 + (k+1) t] (t = layer thickness, z0 = SliceOptions::zStart,
/// by default the mesh's lowest z). Its cross-section is taken on the plane
/// z_k = z0 + (k + planePosition) t; planePosition 0.5 (the default) is mid-layer.
///
/// Robustness: vertices lying exactly on a plane are classified consistently by a symbolic
/// perturbation of the plane towards the layer's middle (z_k + eps when planePosition <= 0.5,
/// z_k - eps otherwise). A vertex on the plane is therefore "below" (or "above") for every
/// triangle that uses it, so every crossed edge is crossed exactly once, horizontal faces on the
/// plane produce nothing, and contours close. Segments are joined through the ids of the mesh
/// edges they cross (never by comparing float coordinates), and each crossing point is computed
/// from the edge's vertices in one fixed order, so both triangles of an edge agree bit for bit.
/// The result is the cross-section just above (or below) the plane, as a clean PolygonSet
/// (Clipper union, positive fill: overlapping shells are merged).
///
/// The mesh must share vertices between triangles (readStl() and makeTestPart() meshes do; for a
/// triangle soup call mergeDuplicateVertices() first), be closed and consistently oriented.

#include <optional>
#include <vector>

#include "vpsim/geometry/mesh.h"
#include "vpsim/geometry/polygons.h"

namespace vpsim::geometry {

/// Options of sliceMesh().
struct SliceOptions {
    double layerThickness = 0.05;  ///< t (mm), > 0
    double planePosition = 0.5;    ///< where the slicing plane lies in the layer, in [0, 1]
    std::optional<double> zStart;  ///< z0 (mm); default: the mesh's lowest z
};

/// One sliced layer.
struct Layer {
    int index = 0;         ///< k
    double zBottom = 0.0;  ///< z0 + k t (mm)
    double z = 0.0;        ///< slicing plane z_k (mm)
    PolygonSet region;     ///< cross-section (outer CCW, holes CW)
};

/// Number of layers covering the mesh: ceil((zmax - z0) / t), ignoring a last sliver thinner than
/// 1e-9 t (so a 10 mm part in 50 um layers has exactly 200).
/// @throw InputError on a non-positive thickness or planePosition outside [0, 1]
int layerCount(const Mesh& mesh, const SliceOptions& options);

/// Slices the mesh. `onlyLayers` selects layer indices (empty: all); out-of-range indices are an
/// error. Layers run in parallel (TBB).
/// @throw InputError when a contour does not close (the mesh is open or inconsistently
///        oriented: read it with readStl(), which checks and repairs)
std::vector<Layer> sliceMesh(const Mesh& mesh, const SliceOptions& options,
                             const std::vector<int>& onlyLayers = {});

/// Cross-section on the single plane z (mm), perturbed upward (perturbUp) or downward.
/// @throw InputError as sliceMesh()
PolygonSet sliceAt(const Mesh& mesh, double z, bool perturbUp = true);

}  // namespace vpsim::geometry
