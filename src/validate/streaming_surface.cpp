#include "vpsim/validate/streaming_surface.h"

#include <array>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/cure/cure_law.h"
#include "vpsim/geometry/mesh_distance.h"

#include "streaming_surface_state.h"

namespace vpsim::validate {

using namespace surface_detail;

StreamingCuredSurface::StreamingCuredSurface(const exposure::ExposureGrid& grid, double voxelHeight,
                                             double isoValue, const geometry::Mesh* part,
                                             double band, const std::string& stlPath)
    : mState(std::make_unique<State>()) {
    State& s = *mState;
    if (!(voxelHeight > 0)) throw InputError("the cured surface needs a positive voxel height");
    s.grid = grid;
    s.voxelHeight = voxelHeight;
    s.iso = isoValue;
    s.curedAt = cure::CureLaw::floatAtLeast(isoValue);
    s.band = band;
    s.statistics = s.tileStatistics = DeviationStatistics(band > 0 ? band : 1.0);
    s.nx = grid.nx;
    s.ny = grid.ny;
    s.P = grid.nx + 2;
    s.Q = grid.ny + 2;
    if (part) s.distance = std::make_unique<geometry::MeshDistance>(*part);
    if (!stlPath.empty()) {
        s.stl = std::make_unique<AtomicFileStream>(stlPath);
        s.stlOut = &s.stl->stream();
        writeStlHeader(*s.stlOut);
    }
}

StreamingCuredSurface::StreamingCuredSurface(const exposure::ExposureGrid& grid, double voxelHeight,
                                             double isoValue, const geometry::Mesh* part,
                                             double band, InPlaceStl stl)
    : StreamingCuredSurface(grid, voxelHeight, isoValue, part, band, "") {
    mState->inPlacePath = stl.path;
}

StreamingCuredSurface::~StreamingCuredSurface() {
    try {
        mState->settle();
    } catch (...) {  // a run that stops here is failing already: its error is the one to report
    }
}

void StreamingCuredSurface::add(const exposure::ExposureSlice& slice) {
    State& s = *mState;
    s.settle();
    if (s.finished) throw InputError("the cured surface was already finished");
    const exposure::SurfaceGrid& values = *slice.values;
    const exposure::CellWindow w = slice.owned();
    // The tile's core and one cell around it (inside the whole grid) must be in the slice.
    if (std::max(0, w.i0 - 1) < values.firstI || std::max(0, w.j0 - 1) < values.firstJ ||
        std::min(s.nx, w.i1 + 1) > values.firstI + values.nx ||
        std::min(s.ny, w.j1 + 1) > values.firstJ + values.ny || w.i1 > s.nx || w.j1 > s.ny)
        throw ResourceError("exposure slice does not match the cured-surface grid");
    s.openInPlace();
    if (w.i0 != s.core.i0 || w.j0 != s.core.j0 || w.i1 != s.core.i1 || w.j1 != s.core.j1)
        s.startTile(w);
    s.advance(&values, slice.z, true);
}

void StreamingCuredSurface::finish() {
    State& s = *mState;
    s.settle();
    if (s.finished) return;
    if (s.started) s.closeTile();
    s.finished = true;
    s.releaseWorkingMemory();
    if (s.triangleCount == 0)
        throw InputError("nothing cured: the exposure never reaches the critical dose (" +
                         formatQuantity(s.iso * 100.0) + " mJ/cm^2)");
    if (s.stlOut) {
        const std::string path = s.stl ? s.stl->path() : s.inPlacePath;
        if (s.triangleCount > UINT32_MAX)
            throw InputError("too many triangles for a binary STL", path);
        const uint32_t count = uint32_t(s.triangleCount);
        s.stlOut->seekp(80);
        s.stlOut->write(reinterpret_cast<const char*>(&count), 4);
        if (s.stl) s.stl->commit();
        if (s.inPlace) {
            s.inPlace->close();
            if (s.inPlace->fail()) throw InputError("cannot write the cured surface", path);
        }
    }
}

uint64_t StreamingCuredSurface::triangles() const {
    mState->settle();
    return mState->triangleCount;
}
double StreamingCuredSurface::volume() const {
    mState->settle();
    return mState->volume;
}
const std::vector<glm::vec3>& StreamingCuredSurface::vertices() const {
    mState->settle();
    return mState->vertices;
}
const std::vector<float>& StreamingCuredSurface::deviations() const {
    mState->settle();
    return mState->deviations;
}
const DeviationStatistics& StreamingCuredSurface::statistics() const {
    mState->settle();
    return mState->statistics;
}
void StreamingCuredSurface::keepTriangles(bool keep) {
    mState->settle();
    mState->keep = keep;
}

void StreamingCuredSurface::keepView(double cell) {
    State& s = *mState;
    s.settle();
    if (s.started || s.triangleCount) throw InputError("the view is kept from the first slice on");
    if (cell > 0) {
        s.keep = false;
        s.clusters = std::make_unique<SurfaceClusters>(cell);
    } else {
        s.keep = true;
        s.clusters.reset();
    }
}

StreamingCuredSurface::View StreamingCuredSurface::view() const {
    const State& s = *mState;
    s.settle();
    if (s.clusters)
        return {s.clusters->mesh(), s.clusters->values(), s.clusters->cell(), s.triangleCount};
    if (!s.keep) return {{}, {}, 0.0, s.triangleCount};
    return {mesh(), s.deviations, 0.0, s.triangleCount};
}

geometry::Mesh StreamingCuredSurface::mesh() const {
    const State& s = *mState;
    s.settle();
    geometry::Mesh mesh;
    mesh.vertices.reserve(s.vertices.size());
    for (const auto& v : s.vertices) mesh.vertices.emplace_back(v);
    // A halo vertex is the owning tile's vertex of the same cube: one watertight mesh.
    mesh.triangles.reserve(s.kept.size());
    for (std::array<uint32_t, 3> tri : s.kept) {
        for (uint32_t& index : tri)
            if (index & HALO) index = s.seamVertices.at(s.haloKeys[index & ~HALO]);
        mesh.triangles.push_back(tri);
    }
    return mesh;
}

}  // namespace vpsim::validate
