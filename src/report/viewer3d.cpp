#include "vpsim/report/viewer3d.h"

#include <cmath>
#include <filesystem>
#include <unordered_map>

#include "viewer3d_js.h"  // generated from assets/viewer3d.js: VIEWER3D_JS
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"

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
    struct Key {
        int64_t x, y, z;
        bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct Hash {
        size_t operator()(const Key& k) const {
            return size_t(k.x * 73856093) ^ size_t(k.y * 19349663) ^ size_t(k.z * 83492791);
        }
    };
    std::unordered_map<Key, uint32_t, Hash> cells;
    std::vector<uint32_t> remap(mesh.vertices.size());
    std::vector<glm::dvec3> sum;
    std::vector<double> valueSum, count;
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        const glm::dvec3& v = mesh.vertices[i];
        Key key{int64_t(std::floor(v.x / cell)), int64_t(std::floor(v.y / cell)),
                int64_t(std::floor(v.z / cell))};
        auto [it, added] = cells.emplace(key, uint32_t(sum.size()));
        if (added) sum.emplace_back(0.0), valueSum.push_back(0), count.push_back(0);
        remap[i] = it->second;
        sum[it->second] += v;
        count[it->second] += 1;
        if (values) valueSum[it->second] += (*values)[i];
    }
    geometry::Mesh out;
    out.vertices.resize(sum.size());
    for (size_t k = 0; k < sum.size(); ++k) out.vertices[k] = sum[k] / count[k];
    for (const auto& t : mesh.triangles) {
        const uint32_t a = remap[t[0]], b = remap[t[1]], c = remap[t[2]];
        if (a != b && b != c && a != c) out.triangles.push_back({a, b, c});
    }
    if (values) {
        values->resize(sum.size());
        for (size_t k = 0; k < sum.size(); ++k) (*values)[k] = float(valueSum[k] / count[k]);
    }
    return out;
}

ViewerSummary writeViewer3d(const std::string& outDir, const geometry::Mesh& cured,
                            const std::vector<float>& deviations, const geometry::Mesh& part,
                            double limitMm, double layerThickness) {
    ViewerSummary s;
    s.curedTriangles = cured.triangles.size();
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

    std::vector<float> microns(deviations.begin(), deviations.end());
    if (microns.size() != cured.vertices.size()) microns.assign(cured.vertices.size(), 0.0f);
    for (float& d : microns) d *= 1000.0f;
    const size_t curedBudget = VIEW_TRIANGLE_BUDGET * 5 / 6, modelBudget = VIEW_TRIANGLE_BUDGET / 6;
    s.clusterCell = cellFor(cured, curedBudget);
    geometry::Mesh curedView = clusterMesh(cured, s.clusterCell, &microns);
    geometry::Mesh modelView = clusterMesh(part, cellFor(part, modelBudget), nullptr);
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
