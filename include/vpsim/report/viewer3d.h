#pragma once
/// @file
/// The cured part in 3D, offline: writes mesh3d.js (the cured surface with its signed deviation
/// per vertex and the model, as base64 Float32/Uint32 arrays in a classic script, since Chromium
/// blocks fetch() and ES modules on file://), viewer3d.js (the viewer) and three.js r111 with
/// its OrbitControls (Debian's libjs-three, copied from VPSIM_THREE_JS_DIR) next to index.html.
/// Meshes above the triangle budget are decimated by vertex clustering for the view, so the
/// report stays under REPORT_SIZE_TARGET on large parts; the summary says by how much.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "vpsim/geometry/mesh.h"
#include "vpsim/report/job_result.h"
#include "vpsim/report/summary_tables.h"
#include "vpsim/validate/streaming_surface.h"

namespace vpsim::report {

/// The size the report's own files (index.html, figures, 3D view) are kept under, bytes.
constexpr uint64_t REPORT_SIZE_TARGET = 50ull << 20;
/// Triangles drawn of the cured and of the model mesh together (about 16 MB of mesh3d.js).
constexpr size_t VIEW_TRIANGLE_BUDGET = 600000;

/// The bytes of `values` in base64 (little-endian, as JavaScript's typed arrays read them).
template <typename T>
std::string base64Of(const std::vector<T>& values) {
    std::string bytes(values.size() * sizeof(T), char(0));
    if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
    return base64(bytes);
}

/// The files the 3D view writes besides the data (in the output directory).
inline constexpr const char* VIEWER_FILES[] = {"three.min.js", "OrbitControls.js", "viewer3d.js",
                                               "mesh3d.js"};

/// A mesh decimated by vertex clustering on a grid of `cell` mm: vertices in one cell merge into
/// their mean (values averaged), triangles that collapse are dropped. cell <= 0 copies.
geometry::Mesh clusterMesh(const geometry::Mesh& mesh, double cell, std::vector<float>* values);

/// The cured surface's share of the view's triangles (the model has the rest).
constexpr size_t CURED_VIEW_BUDGET = VIEW_TRIANGLE_BUDGET * 5 / 6;
/// The cell (mm) on which the mesher clusters the cured surface for the pictures
/// (StreamingCuredSurface::keepView), from the part's area (mm^2), which the cured surface's is
/// near: 0 (every triangle) when the mesher's own triangles, about 3 area / (voxel min(voxel,
/// height)) (12e6 measured on the 400 mm^2 block at 10 um), fit CURED_VIEW_BUDGET.
double viewCell(double partArea, double voxel, double voxelHeight);

/// Writes the view's files into `outDir`: the cured surface as kept (deviations in mm per
/// vertex), clustered further if still above the budget; `limitMm` the colour scale's ends.
/// Without three.js installed nothing is written and `missing` says why.
/// @throw InputError when a file cannot be written
ViewerSummary writeViewer3d(const std::string& outDir,
                            const validate::StreamingCuredSurface::View& cured,
                            const geometry::Mesh& part, double limitMm, double layerThickness);

}  // namespace vpsim::report
