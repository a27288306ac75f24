#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <glm/geometric.hpp>

#include "exposure/avx2_clones.h"

#include "streaming_surface_state.h"

namespace vpsim::validate {
namespace surface_detail {

VPSIM_AVX2_CLONES void mixedCubes(const uint8_t* __restrict a0, const uint8_t* __restrict a1,
                                  const uint8_t* __restrict b0, const uint8_t* __restrict b1,
                                  uint8_t* __restrict mask, int cubes) {
    for (int i = 0; i < cubes; ++i) {
        const uint8_t x = a0[i];
        mask[i] = uint8_t((x ^ a0[i + 1]) | (x ^ a1[i]) | (x ^ a1[i + 1]) | (x ^ b0[i]) |
                          (x ^ b0[i + 1]) | (x ^ b1[i]) | (x ^ b1[i + 1]));
    }
}

VPSIM_AVX2_CLONES void crossingEdges(const uint8_t* __restrict above,
                                     const uint8_t* __restrict below, int width,
                                     uint8_t* __restrict mask, int samples) {
    for (int i = 0; i < samples; ++i) {
        const uint8_t x = above[i];
        mask[i] = uint8_t((x ^ below[i]) | (x ^ above[i + 1]) | (x ^ above[i + width]));
    }
}

/// The next index from `i` on whose mask is not zero, or `end`: eight at a time over zeros.
int nextSet(const uint8_t* mask, int i, int end) {
    while (i + 8 <= end && load8(mask + i) == 0) i += 8;
    while (i < end && mask[i] == 0) ++i;
    return i;
}

}  // namespace surface_detail

using namespace surface_detail;

namespace {

/// in[i] = v[i] >= threshold (CureLaw::isCured), for n values. A function of its own so that the
/// threshold and the count are locals: the flags are bytes, which may alias a member or a
/// captured reference, and those would be read again for every flag (no vectorised loop).
void cureFlags(const float* v, uint8_t* in, int n, float threshold) {
    for (int i = 0; i < n; ++i) in[i] = v[i] >= threshold;
}

}  // namespace

void StreamingCuredSurface::State::load(PaddedSlice& target, const exposure::SurfaceGrid* values,
                                        double z) {
    target.z = z;
    // Samples of the whole grid's cells (pi - 1, pj - 1) come from the slice; the padding
    // around the whole grid is zero.
    const int liLo = std::max(0, 1 - sx0), liHi = std::min(W, nx + 1 - sx0);
    tbb::parallel_for(0, H, [&](int lj) {
        float* v = &target.value[sample(0, lj)];
        uint8_t* in = &target.in[sample(0, lj)];
        const int cj = sy0 + lj - 1;
        if (values && cj >= 0 && cj < ny && liLo < liHi) {
            const float* row = &values->values[size_t(cj - values->firstJ) * values->nx +
                                               size_t(sx0 + liLo - 1 - values->firstI)];
            std::fill(v, v + liLo, 0.0f);
            std::memcpy(v + liLo, row, sizeof(float) * size_t(liHi - liLo));
            std::fill(v + liHi, v + W, 0.0f);
        } else {
            std::fill(v, v + W, 0.0f);
        }
        cureFlags(v, in, W, curedAt);
    });
}

glm::dvec3 StreamingCuredSurface::State::cubeVertex(int li, int lj) const {
    glm::dvec3 sum(0.0);
    int count = 0;
    auto edge = [&](const PaddedSlice& sa, size_t a, const PaddedSlice& sb, size_t b,
                    const glm::dvec3& pa, const glm::dvec3& pb) {
        if (sa.in[a] == sb.in[b]) return;
        const double va = sa.value[a], vb = sb.value[b];
        const double t = std::clamp((iso - va) / (vb - va), 0.0, 1.0);
        sum += pa + t * (pb - pa);
        ++count;
    };
    const int ci = sx0 + li, cj = sy0 + lj;
    for (int s = 0; s < 2; ++s) {
        const PaddedSlice& sl = s == 0 ? above : below;
        for (int dj = 0; dj < 2; ++dj)  // x edges
            edge(sl, sample(li, lj + dj), sl, sample(li + 1, lj + dj), position(ci, cj + dj, sl.z),
                 position(ci + 1, cj + dj, sl.z));
        for (int di = 0; di < 2; ++di)  // y edges
            edge(sl, sample(li + di, lj), sl, sample(li + di, lj + 1), position(ci + di, cj, sl.z),
                 position(ci + di, cj + 1, sl.z));
    }
    for (int dj = 0; dj < 2; ++dj)  // z edges
        for (int di = 0; di < 2; ++di)
            edge(above, sample(li + di, lj + dj), below, sample(li + di, lj + dj),
                 position(ci + di, cj + dj, above.z), position(ci + di, cj + dj, below.z));
    return sum / double(std::max(count, 1));
}

bool StreamingCuredSurface::State::ownsCube(int ci, int cj) const {
    return ci >= own.i0 && ci < own.i1 && cj >= own.j0 && cj < own.j1;
}

StreamingCuredSurface::State::NewVertices StreamingCuredSurface::State::buildLayer() {
    trimVertices();
    for (uint32_t c : filledBelow) layerBelow[c] = NONE;
    filledBelow.clear();
    tbb::parallel_for(tbb::blocked_range<int>(0, H - 1), [&](const tbb::blocked_range<int>& rows) {
        std::vector<uint8_t> mixed(size_t(W - 1));
        for (int lj = rows.begin(); lj < rows.end(); ++lj) {
            auto& out = rowVertices[lj];
            out.clear();
            mixedCubes(&above.in[sample(0, lj)], &above.in[sample(0, lj + 1)],
                       &below.in[sample(0, lj)], &below.in[sample(0, lj + 1)], mixed.data(), W - 1);
            for (int li = nextSet(mixed.data(), 0, W - 1); li < W - 1;
                 li = nextSet(mixed.data(), li + 1, W - 1))
                out.emplace_back(li, glm::vec3(cubeVertex(li, lj)));
        }
    });
    // Owned vertices are numbered in row order; the halo's are kept apart.
    std::vector<size_t> first(H, vertices.size());
    for (int lj = 0; lj < H - 1; ++lj) {
        size_t owned = 0;
        for (const auto& entry : rowVertices[lj]) owned += ownsCube(sx0 + entry.first, sy0 + lj);
        first[lj + 1] = first[lj] + owned;
    }
    layerStart = base + vertices.size();
    haloAbove = haloVertices.size();
    vertices.resize(first[H - 1]);
    deviations.resize(first[H - 1]);
    tbb::parallel_for(0, H - 1, [&](int lj) {
        size_t v = first[lj];
        uint32_t nearest = geometry::MeshDistance::NO_HINT;  // the row's vertices are neighbours
        auto& proofs = nearestProofs.local();
        for (const auto& [li, p] : rowVertices[lj]) {
            if (!ownsCube(sx0 + li, sy0 + lj)) continue;
            vertices[v] = p;
            deviations[v] =
                distance
                    ? float(std::clamp(distance->signedDistance(glm::dvec3(p), nearest, proofs),
                                       -band, band))
                    : 0.0f;
            layerBelow[cube(li, lj)] = uint32_t(v);
            ++v;
        }
    });
    for (int lj = 0; lj < H - 1; ++lj)
        for (const auto& [li, p] : rowVertices[lj]) {
            const int ci = sx0 + li, cj = sy0 + lj;
            filledBelow.push_back(uint32_t(cube(li, lj)));
            if (!ownsCube(ci, cj)) {
                layerBelow[cube(li, lj)] = HALO | uint32_t(haloVertices.size());
                haloVertices.push_back(p);
                if (keep) haloKeys.push_back(cubeKey(ci, cj));
            } else if (keep &&
                       ((ci == own.i1 - 1 && own.i1 < P) || (cj == own.j1 - 1 && own.j1 < Q))) {
                seamVertices.emplace(cubeKey(ci, cj), layerBelow[cube(li, lj)]);
            }
        }
    return {first[0], first[H - 1], haloAbove};
}

void StreamingCuredSurface::State::addVertices(const NewVertices& made) {
    for (size_t v = made.from; v < made.to; ++v) tileStatistics.add(deviations[v]);
    if (!clusters) return;
    vertexCluster.resize(made.to);
    for (size_t v = made.from; v < made.to; ++v)
        vertexCluster[v] = clusters->add(glm::dvec3(vertices[v]), deviations[v]);
    // At its owner's position (made from the same values): the owner's cluster.
    haloCluster.resize(haloVertices.size());
    for (size_t h = made.haloFrom; h < haloVertices.size(); ++h)
        haloCluster[h] = clusters->add(glm::dvec3(haloVertices[h]), 0.0f, false);
}

void StreamingCuredSurface::State::emitQuads(const NewVertices& made) {
    // The vertices go into the statistics and clusters (serial) while the quads are made.
    tbb::task_group vertexWork;
    vertexWork.run([&] { addVertices(made); });
    try {
        makeQuads();
    } catch (...) {
        try {
            vertexWork.wait();
        } catch (...) {  // the quads' error is the one to report
        }
        throw;
    }
    vertexWork.wait();
    for (int lj = own.j0 - sy0; lj < std::min(own.j1, Q - 1) - sy0; ++lj) record(rowTriangles[lj]);
}

void StreamingCuredSurface::State::makeQuads() {
    const int ljLo = own.j0 - sy0, ljHi = std::min(own.j1, Q - 1) - sy0;
    const int liLo = own.i0 - sx0, liHi = std::min(own.i1, P - 1) - sx0;
    auto emitRow = [&](int lj, uint8_t* crossing) {
        auto& out = rowTriangles[lj];
        out.clear();
        double moment = 0;
        auto quad = [&](uint32_t q0, uint32_t q1, uint32_t q2, uint32_t q3, bool flip) {
            if (flip) std::swap(q1, q3);
            const std::array<uint32_t, 3> t[2] = {{q0, q1, q2}, {q0, q2, q3}};
            for (const auto& tri : t) {
                out.push_back(tri);
                const glm::dvec3 a = glm::dvec3(vertex(tri[0])) - reference,
                                 b = glm::dvec3(vertex(tri[1])) - reference,
                                 c = glm::dvec3(vertex(tri[2])) - reference;
                moment += glm::dot(a, glm::cross(b, c));
            }
        };
        const int pj = sy0 + lj;
        const bool realRow = pj >= 1 && pj <= ny;
        // The row's flags through locals: read through the members, each flag would read the
        // vectors' data pointers again (bytes may alias them).
        const int width = W;
        const uint8_t* up = &above.in[sample(0, lj)];
        const uint8_t* down = &below.in[sample(0, lj)];
        crossingEdges(up + liLo, down + liLo, width, crossing, liHi - liLo);
        for (int at = nextSet(crossing, 0, liHi - liLo); at < liHi - liLo;
             at = nextSet(crossing, at + 1, liHi - liLo)) {
            const int li = liLo + at;
            const int pi = sx0 + li;
            const bool realColumn = pi >= 1 && pi <= nx;
            const uint8_t a = up[li], b = down[li];
            if (realRow && realColumn && a != b)  // z edge
                quad(layerBelow[cube(li - 1, lj - 1)], layerBelow[cube(li, lj - 1)],
                     layerBelow[cube(li, lj)], layerBelow[cube(li - 1, lj)], !(b && !a));
            if (realRow && a != up[li + 1])  // x edge (pi, pi + 1)
                quad(layerBelow[cube(li, lj - 1)], layerBelow[cube(li, lj)],
                     layerAbove[cube(li, lj)], layerAbove[cube(li, lj - 1)], !(a && !up[li + 1]));
            if (realColumn && a != up[li + width])  // y edge (pj, pj + 1)
                quad(layerBelow[cube(li - 1, lj)], layerAbove[cube(li - 1, lj)],
                     layerAbove[cube(li, lj)], layerBelow[cube(li, lj)], !(a && !up[li + width]));
        }
        rowVolume[lj] = moment;
    };
    tbb::parallel_for(tbb::blocked_range<int>(ljLo, ljHi),
                      [&](const tbb::blocked_range<int>& rows) {
                          std::vector<uint8_t> crossing(size_t(std::max(0, liHi - liLo)));
                          for (int lj = rows.begin(); lj < rows.end(); ++lj)
                              emitRow(lj, crossing.data());
                      });
    // The STL records of a group of rows are made in parallel, then written in row order; a
    // group of about STL_GROUP triangles at a time, so that a flat face (two triangles a cell)
    // needs no slice-sized buffer and a layer of side walls is one group, not one per few rows.
    for (int group = ljLo; group < ljHi;) {
        int end = group;
        size_t count = 0;
        std::vector<size_t>& offset = groupOffsets;
        offset.assign(1, 0);
        while (end < ljHi && (end == group || count + rowTriangles[end].size() <= STL_GROUP)) {
            count += rowTriangles[end++].size();
            offset.push_back(count);
        }
        if (stlOut && count > 0) {
            groupStl.resize(count * STL_RECORD);
            tbb::parallel_for(group, end, [&](int lj) {
                formatStl(rowTriangles[lj], &groupStl[offset[lj - group] * STL_RECORD]);
            });
            stlOut->write(groupStl.data(), std::streamsize(groupStl.size()));
        }
        for (int lj = group; lj < end; ++lj) tileVolume += rowVolume[lj] / 6.0;
        group = end;
    }
}

void StreamingCuredSurface::State::record(const std::vector<std::array<uint32_t, 3>>& triangles) {
    triangleCount += triangles.size();
    if (keep) kept.insert(kept.end(), triangles.begin(), triangles.end());
    if (clusters)
        for (const auto& tri : triangles)
            clusters->addTriangle(clusterOf(tri[0]), clusterOf(tri[1]), clusterOf(tri[2]));
}

void StreamingCuredSurface::State::formatStl(const std::vector<std::array<uint32_t, 3>>& triangles,
                                             char* p) const {
    for (const auto& tri : triangles) {
        const glm::vec3 &a = vertex(tri[0]), &b = vertex(tri[1]), &c = vertex(tri[2]);
        glm::vec3 n = glm::cross(b - a, c - a);
        const float length = glm::length(n);
        n = length > 0 ? n / length : glm::vec3(0.0f);
        const float f[12] = {n.x, n.y, n.z, a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
        std::memcpy(p, f, sizeof f);
        std::memset(p + 48, 0, 2);
        p += 50;
    }
}

void StreamingCuredSurface::State::advance(const exposure::SurfaceGrid* values, double z,
                                           bool inBackground) {
    settle();
    if (!started) {
        load(above, nullptr, z + voxelHeight);
        if (!referenceSet) reference = position(0, 0, z);
        referenceSet = true;
        started = true;
    }
    load(below, values, z);
    auto makeLayer = [this] {
        emitQuads(buildLayer());
        std::swap(above, below);
        std::swap(layerAbove, layerBelow);
        std::swap(filledAbove, filledBelow);
        ++step;
    };
    if (!inBackground) return makeLayer();
    layerPending = true;
    // Isolated: a thread waiting inside the layer's own parallel loops must not take up another
    // slice's add(), whose settle() would wait for this very layer below it on the stack (seen as
    // a hang with 16 worker threads).
    layerWork.run([makeLayer] { tbb::this_task_arena::isolate(makeLayer); });
}

void StreamingCuredSurface::State::settle() const {
    if (!layerPending) return;
    layerPending = false;
    layerWork.wait();
}

}  // namespace vpsim::validate
