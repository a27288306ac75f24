#include "vpsim/report/viewer3d.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "viewer3d_js.h"  // generated from assets/viewer3d.js: VIEWER3D_JS
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/validate/surface_clusters.h"

#ifndef VPSIM_THREE_JS_DIR
#define VPSIM_THREE_JS_DIR "/usr/share/javascript/three"
#endif

namespace vpsim::report {
namespace {

/// {"positions": base64 Float32 xyz, "indices": base64 Uint32} of a mesh, centred on `centre`.
std::string meshJs(const geometry::Mesh& mesh, const glm::dvec3& centre) {
    std::vector<float> positions;
    positions.reserve(mesh.vertices.size() * 3);
    for (const glm::dvec3& v : mesh.vertices)
        positions.insert(positions.end(),
                         {float(v.x - centre.x), float(v.y - centre.y), float(v.z - centre.z)});
    std::vector<uint32_t> indices;
    indices.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    return "{\"positions\":\"" + base64Of(positions) + "\",\"indices\":\"" + base64Of(indices) +
           "\"}";
}

/// The clustering cell that brings `triangles` near `budget` (triangles scale as 1/cell^2 on a
/// surface), from the mesh's area.
double cellFor(const geometry::Mesh& mesh, size_t budget) {
    if (mesh.triangles.size() <= budget) return 0;
    // A clustered surface of area A on cells of size c has about 2 A / c^2 triangles.
    return std::sqrt(2.0 * mesh.area() / double(budget));
}

}  // namespace

geometry::Mesh clusterMesh(const geometry::Mesh& mesh, double cell, std::vector<float>* values) {
    if (!(cell > 0)) return mesh;
    validate::SurfaceClusters clusters(cell);
    std::vector<uint32_t> remap(mesh.vertices.size());
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
        remap[i] = clusters.add(mesh.vertices[i], values ? (*values)[i] : 0.0f);
    for (const auto& t : mesh.triangles)
        clusters.addTriangle(remap[t[0]], remap[t[1]], remap[t[2]]);
    if (values) *values = clusters.values();
    return clusters.mesh();
}

double viewCell(double area, double voxel, double voxelHeight) {
    // A layered cured surface is rougher and larger than the model's: 495 mm^2 measured for the
    // 400 mm^2 block at 10 um, clustering to 1.7 times the flat surface's 2 A / cell^2.
    const double curedArea = 1.25 * area;
    const double made = 3.0 * curedArea / (voxel * std::min(voxel, voxelHeight));
    if (!(made > double(CURED_VIEW_BUDGET))) return 0;
    return std::sqrt(1.5 * 2.0 * curedArea / double(CURED_VIEW_BUDGET));
}

ViewerSummary writeViewer3d(const std::string& outDir,
                            const validate::StreamingCuredSurface::View& view,
                            const geometry::Mesh& part, double limitMm, double layerThickness) {
    const geometry::Mesh& cured = view.mesh;
    ViewerSummary s;
    s.curedTriangles = view.madeTriangles;
    s.modelTriangles = part.triangles.size();
    s.limitUm = limitMm * 1000;
    s.layerThickness = layerThickness;
    const std::string three = std::string(VPSIM_THREE_JS_DIR) + "/three.min.js";
    const std::string controls =
        std::string(VPSIM_THREE_JS_DIR) + "/examples/js/controls/OrbitControls.js";
    std::error_code error;
    if (!std::filesystem::is_regular_file(three, error) ||
        !std::filesystem::is_regular_file(controls, error)) {
        s.missing = "three.js (Debian package libjs-three) is not installed at " +
                    std::string(VPSIM_THREE_JS_DIR) + "; tools/install-deps.sh installs it";
        return s;
    }
    writeFileAtomic(outDir + "/three.min.js", readFile(three));
    writeFileAtomic(outDir + "/OrbitControls.js", readFile(controls));
    writeFileAtomic(outDir + "/viewer3d.js", VIEWER3D_JS);

    std::vector<float> microns(view.deviations.begin(), view.deviations.end());
    if (microns.size() != cured.vertices.size()) microns.assign(cured.vertices.size(), 0.0f);
    for (float& d : microns) d *= 1000.0f;
    // Clustered again when the kept picture outgrew the budget (a cured surface much larger than
    // the part): a cell at least that much coarser than the picture's own.
    const double ratio = std::sqrt(double(cured.triangles.size()) / double(CURED_VIEW_BUDGET));
    const double again =
        ratio > 1 ? std::max(cellFor(cured, CURED_VIEW_BUDGET), view.cell * ratio * 1.1) : 0.0;
    s.clusterCell = std::max(view.cell, again);
    geometry::Mesh curedView = clusterMesh(cured, again, &microns);
    geometry::Mesh modelView = clusterMesh(part, cellFor(part, VIEW_TRIANGLE_BUDGET / 6), nullptr);
    s.curedShown = curedView.triangles.size();
    s.modelShown = modelView.triangles.size();
    geometry::Bounds b = part.bounds();
    const geometry::Bounds cb = cured.bounds();
    if (!cb.empty()) b.add(cb.lo), b.add(cb.hi);
    const glm::dvec3 centre{(b.lo.x + b.hi.x) / 2, (b.lo.y + b.hi.y) / 2, b.lo.z};
    std::string js = "window.VPSIM_MESH={\"cured\":" + meshJs(curedView, centre) +
                     ",\"deviation_um\":\"" + base64Of(microns) +
                     "\",\"model\":" + meshJs(modelView, centre) +
                     ",\"limit_um\":" + formatNumber(s.limitUm, 6) +
                     ",\"layer_mm\":" + formatNumber(layerThickness, 6) +
                     ",\"height_mm\":" + formatNumber(b.hi.z - b.lo.z, 6) + "};\n";
    s.dataBytes = js.size();
    writeFileAtomic(outDir + "/mesh3d.js", js);
    return s;
}

}  // namespace vpsim::report
