// A tile's working memory in the streamed cured surface: the in-place STL file, starting and
// closing a tile (its owned cubes, padded slices and vertex tables), dropping the vertices no
// later layer refers to, and releasing the buffers once the surface is finished.
#include <algorithm>
#include <fstream>

#include "vpsim/core/error.h"

#include "streaming_surface_state.h"

namespace vpsim::validate {

using namespace surface_detail;

void StreamingCuredSurface::State::openInPlace() {
    if (inPlacePath.empty() || inPlace) return;
    inPlace = std::make_unique<std::fstream>(inPlacePath,
                                             std::ios::out | std::ios::trunc | std::ios::binary);
    if (!*inPlace) throw InputError("cannot write the cured surface", inPlacePath);
    stlOut = inPlace.get();
    writeStlHeader(*stlOut);
}

namespace {

template <class T>
void release(T& container) {
    T().swap(container);
}

}  // namespace

void StreamingCuredSurface::State::releaseWorkingMemory() {
    for (PaddedSlice* slice : {&above, &below}) {
        release(slice->value);
        release(slice->in);
    }
    release(layerAbove);
    release(layerBelow);
    release(filledAbove);
    release(filledBelow);
    release(rowVertices);
    release(rowTriangles);
    release(rowVolume);
    release(groupStl);
    release(groupOffsets);
    release(vertexCluster);
    release(haloCluster);
    if (keep) return;  // the view's mesh needs them
    release(vertices);
    release(deviations);
    release(haloVertices);
    release(haloKeys);
}

void StreamingCuredSurface::State::startTile(const exposure::CellWindow& w) {
    if (started) closeTile();
    core = w;
    own = {w.i0 == 0 ? 0 : w.i0 + 1, w.j0 == 0 ? 0 : w.j0 + 1, w.i1 == nx ? P : w.i1 + 1,
           w.j1 == ny ? Q : w.j1 + 1};
    sx0 = std::max(0, own.i0 - 1);
    sy0 = std::max(0, own.j0 - 1);
    W = std::min(P, own.i1 + 1) - sx0;
    H = std::min(Q, own.j1 + 1) - sy0;
    for (PaddedSlice* slice : {&above, &below}) {
        slice->value.assign(size_t(W) * H, 0.0f);
        slice->in.assign(size_t(W) * H, 0);
    }
    if (!keep) {  // only the kept triangles refer to earlier tiles'
        haloVertices.clear();
        haloCluster.clear();
        haloAbove = 0;
    }
    layerStart = base + vertices.size();  // nothing of an earlier tile is referred to
    layerAbove.assign(size_t(W - 1) * (H - 1), NONE);
    layerBelow = layerAbove;
    filledAbove.clear();
    filledBelow.clear();
    rowVertices.resize(H - 1);
    rowTriangles.resize(H);
    rowVolume.assign(H, 0.0);
    step = 0;
}

void StreamingCuredSurface::State::closeTile() {
    advance(nullptr, above.z - voxelHeight);
    started = false;
    if (clusters) clusters->endTile();
    statistics.merge(tileStatistics);
    tileStatistics = DeviationStatistics(statistics.band());
    volume += tileVolume;
    tileVolume = 0;
}

void StreamingCuredSurface::State::trimVertices() {
    if (keep) return;
    const uint64_t drop = layerStart - base;
    const size_t haloDrop = haloAbove;
    if (drop == 0 && haloDrop == 0) return;
    vertices.erase(vertices.begin(), vertices.begin() + std::ptrdiff_t(drop));
    deviations.erase(deviations.begin(), deviations.begin() + std::ptrdiff_t(drop));
    haloVertices.erase(haloVertices.begin(), haloVertices.begin() + std::ptrdiff_t(haloDrop));
    if (clusters) {
        vertexCluster.erase(vertexCluster.begin(), vertexCluster.begin() + std::ptrdiff_t(drop));
        haloCluster.erase(haloCluster.begin(), haloCluster.begin() + std::ptrdiff_t(haloDrop));
    }
    base = layerStart;
    for (uint32_t c : filledAbove) {  // the cubes with a vertex in layerAbove
        uint32_t& index = layerAbove[c];
        index -= uint32_t(index & HALO ? haloDrop : drop);
    }
}

}  // namespace vpsim::validate
