#include "vpsim/validate/streaming_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unordered_map>

#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/cure/cure_law.h"
#include "vpsim/geometry/mesh_distance.h"

namespace vpsim::validate {
namespace {

void writeStlHeader(std::ostream& out) {
    char header[84] = {};
    const std::string text = "vpsim binary STL, mm: cured";
    std::memcpy(header, text.data(), text.size());
    out.write(header, 84);
}

constexpr uint32_t NONE = UINT32_MAX;
constexpr uint32_t HALO = 0x80000000u;  ///< a vertex index into the halo's vertices

/// A slice padded with one zero cell on every side: (nx + 2) x (ny + 2) values and cured flags.
struct PaddedSlice {
    std::vector<float> value;
    std::vector<uint8_t> in;
    double z = 0;
};

uint64_t load8(const uint8_t* p) {
    uint64_t word;
    std::memcpy(&word, p, 8);
    return word;
}

/// Whether the eight cubes from each pointer on (rows j, j + 1 of the slices above and below,
/// 0/1 flags) are each all inside or all outside.
bool uniform8(const uint8_t* a0, const uint8_t* a1, const uint8_t* b0, const uint8_t* b1) {
    const uint64_t x = load8(a0);
    return ((x ^ load8(a0 + 1)) | (x ^ load8(a1)) | (x ^ load8(a1 + 1)) | (x ^ load8(b0)) |
            (x ^ load8(b0 + 1)) | (x ^ load8(b1)) | (x ^ load8(b1 + 1))) == 0;
}

/// Whether none of eight samples from `above` on has a crossing z, x or y edge (row width W).
bool noEdge8(const uint8_t* above, const uint8_t* below, int width) {
    const uint64_t x = load8(above);
    return ((x ^ load8(below)) | (x ^ load8(above + 1)) | (x ^ load8(above + width))) == 0;
}

}  // namespace

struct StreamingCuredSurface::State {
    exposure::ExposureGrid grid;
    double voxelHeight, iso, band;
    float curedAt = 0;  ///< v >= curedAt exactly when double(v) >= iso (CureLaw::floatAtLeast)
    std::unique_ptr<geometry::MeshDistance> distance;
    std::unique_ptr<AtomicFileStream> stl;
    /// The STL written in place (resumable: it survives a kill), opened at the first slice or
    /// by restoreState.
    std::string inPlacePath;
    std::unique_ptr<std::fstream> inPlace;
    std::ostream* stlOut = nullptr;  ///< the STL's stream, or none
    int nx, ny, P, Q;                ///< whole grid's cells; its padded width and height
    // The current tile, in padded samples of the whole grid: it owns the samples (and the edges
    // and cubes that start there) in [own.i0, own.i1) x [own.j0, own.j1) and holds the samples
    // in [sx0, sx0 + W) x [sy0, sy0 + H): one more on each side, for the cubes its edges join.
    exposure::CellWindow core{0, 0, -1, -1}, own;
    int sx0 = 0, sy0 = 0, W = 0, H = 0;
    int step = 0;  ///< cube layers made in this tile (every tile makes the same layers)
    PaddedSlice above, below;
    bool started = false, finished = false, referenceSet = false;
    std::vector<uint32_t> layerAbove, layerBelow;  ///< vertex per cube, (W - 1) x (H - 1)
    /// The cubes given a vertex in layerAbove and layerBelow: only those are cleared for the
    /// next layer (the whole layer would be 4 bytes a cell per slice).
    std::vector<uint32_t> filledAbove, filledBelow;
    /// Vertices of the cubes the tiles own and their deviations: all of them when the
    /// triangles are kept, else from the layer above on (trimVertices), vertices[0] being the
    /// run's vertex number `base`: memory follows a layer of the tile, not the surface.
    std::vector<glm::vec3> vertices;
    std::vector<float> deviations;
    uint64_t base = 0, layerStart = 0;  ///< numbers of vertices[0] and of the layer above's first
    /// Deviations of this tile (in the order made) and of the finished tiles (merged in order).
    DeviationStatistics tileStatistics, statistics;
    /// Cubes beside the tile that another tile owns: their vertices are made again (from the
    /// same values, so at the same positions) and referred to as HALO | index.
    std::vector<glm::vec3> haloVertices;
    std::vector<uint64_t> haloKeys;  ///< cube keys of haloVertices (when triangles are kept)
    size_t haloAbove = 0;            ///< haloVertices before the layer above's
    std::unordered_map<uint64_t, uint32_t> seamVertices;  ///< owned cubes a neighbour makes too
    std::vector<std::vector<std::pair<int, glm::vec3>>> rowVertices;
    std::vector<std::vector<std::array<uint32_t, 3>>> rowTriangles;
    std::vector<double> rowVolume;
    std::vector<std::array<uint32_t, 3>> kept;
    bool keep = false;
    uint64_t triangleCount = 0;
    double volume = 0, tileVolume = 0;  ///< the finished tiles', and this tile's (merged in order)
    glm::dvec3 reference{0.0};  ///< volume moments are taken about this point (less rounding)
    std::vector<char> buffer;

    size_t sample(int li, int lj) const { return size_t(lj) * W + li; }
    size_t cube(int li, int lj) const { return size_t(lj) * (W - 1) + li; }
    /// Position of the whole grid's padded sample (pi, pj).
    glm::dvec3 position(int pi, int pj, double z) const {
        return {grid.originX + (pi - 0.5) * grid.pitch, grid.originY + (pj - 0.5) * grid.pitch, z};
    }
    const glm::vec3& vertex(uint32_t index) const {
        return index & HALO ? haloVertices[index & ~HALO] : vertices[index];
    }
    uint64_t cubeKey(int ci, int cj) const {
        return (uint64_t(step) * uint64_t(Q - 1) + uint64_t(cj)) * uint64_t(P - 1) + uint64_t(ci);
    }

    /// A fresh in-place STL, opened by the first tile made or merged (not by restoreState).
    void openInPlace() {
        if (inPlacePath.empty() || inPlace) return;
        inPlace = std::make_unique<std::fstream>(
            inPlacePath, std::ios::out | std::ios::trunc | std::ios::binary);
        if (!*inPlace) throw InputError("cannot write the cured surface", inPlacePath);
        stlOut = inPlace.get();
        writeStlHeader(*stlOut);
    }

    /// Starts the tile whose core cells are `w` (the whole grid when untiled).
    void startTile(const exposure::CellWindow& w) {
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

    /// The tile's bottom: the zero padding below its last slice closes its part of the mesh.
    void closeTile() {
        advance(nullptr, above.z - voxelHeight);
        started = false;
        statistics.merge(tileStatistics);
        tileStatistics = DeviationStatistics(statistics.band());
        volume += tileVolume;
        tileVolume = 0;
    }

    /// Without kept triangles, only the layer above's vertices are referred to again: drops the
    /// older ones (owned and halo) and renumbers layerAbove's references.
    void trimVertices() {
        if (keep) return;
        const uint64_t drop = layerStart - base;
        const size_t haloDrop = haloAbove;
        if (drop == 0 && haloDrop == 0) return;
        vertices.erase(vertices.begin(), vertices.begin() + std::ptrdiff_t(drop));
        deviations.erase(deviations.begin(), deviations.begin() + std::ptrdiff_t(drop));
        haloVertices.erase(haloVertices.begin(), haloVertices.begin() + std::ptrdiff_t(haloDrop));
        base = layerStart;
        for (uint32_t& index : layerAbove)
            if (index != NONE) index -= uint32_t(index & HALO ? haloDrop : drop);
    }

    void load(PaddedSlice& target, const exposure::SurfaceGrid* values, double z) {
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
            for (int li = 0; li < W; ++li) in[li] = v[li] >= curedAt;  // CureLaw::isCured
        });
    }

    /// The vertex of local cube (li, lj) between `above` and `below`: the mean of its edge
    /// crossings.
    glm::dvec3 cubeVertex(int li, int lj) const {
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
                edge(sl, sample(li, lj + dj), sl, sample(li + 1, lj + dj),
                     position(ci, cj + dj, sl.z), position(ci + 1, cj + dj, sl.z));
            for (int di = 0; di < 2; ++di)  // y edges
                edge(sl, sample(li + di, lj), sl, sample(li + di, lj + 1),
                     position(ci + di, cj, sl.z), position(ci + di, cj + 1, sl.z));
        }
        for (int dj = 0; dj < 2; ++dj)  // z edges
            for (int di = 0; di < 2; ++di)
                edge(above, sample(li + di, lj + dj), below, sample(li + di, lj + dj),
                     position(ci + di, cj + dj, above.z), position(ci + di, cj + dj, below.z));
        return sum / double(std::max(count, 1));
    }

    bool ownsCube(int ci, int cj) const {
        return ci >= own.i0 && ci < own.i1 && cj >= own.j0 && cj < own.j1;
    }

    /// Vertices of the cubes between `above` and `below` into layerBelow, rows in parallel and
    /// numbered in row order.
    void buildLayer() {
        trimVertices();
        for (uint32_t c : filledBelow) layerBelow[c] = NONE;
        filledBelow.clear();
        tbb::parallel_for(0, H - 1, [&](int lj) {
            auto& out = rowVertices[lj];
            out.clear();
            const uint8_t *a0 = &above.in[sample(0, lj)], *a1 = &above.in[sample(0, lj + 1)],
                          *b0 = &below.in[sample(0, lj)], *b1 = &below.in[sample(0, lj + 1)];
            for (int li = 0; li < W - 1; ++li) {
                if (li % 8 == 0 && li + 8 < W && uniform8(a0 + li, a1 + li, b0 + li, b1 + li)) {
                    li += 7;  // eight cubes all inside or all outside: no vertex
                    continue;
                }
                const int sum = a0[li] + a0[li + 1] + a1[li] + a1[li + 1] + b0[li] + b0[li + 1] +
                                b1[li] + b1[li + 1];
                if (sum == 0 || sum == 8) continue;
                out.emplace_back(li, glm::vec3(cubeVertex(li, lj)));
            }
        });
        // Owned vertices are numbered in row order; the halo's are kept apart.
        std::vector<size_t> first(H, vertices.size());
        for (int lj = 0; lj < H - 1; ++lj) {
            size_t owned = 0;
            for (const auto& entry : rowVertices[lj])
                owned += ownsCube(sx0 + entry.first, sy0 + lj);
            first[lj + 1] = first[lj] + owned;
        }
        layerStart = base + vertices.size();
        haloAbove = haloVertices.size();
        vertices.resize(first[H - 1]);
        deviations.resize(first[H - 1]);
        tbb::parallel_for(0, H - 1, [&](int lj) {
            size_t v = first[lj];
            uint32_t nearest =
                geometry::MeshDistance::NO_HINT;  // the row's vertices are neighbours
            for (const auto& [li, p] : rowVertices[lj]) {
                if (!ownsCube(sx0 + li, sy0 + lj)) continue;
                vertices[v] = p;
                deviations[v] =
                    distance ? float(std::clamp(distance->signedDistance(glm::dvec3(p), nearest),
                                                -band, band))
                             : 0.0f;
                layerBelow[cube(li, lj)] = uint32_t(v);
                ++v;
            }
        });
        for (size_t v = first[0]; v < first[H - 1]; ++v) tileStatistics.add(deviations[v]);
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
    }

    /// Quads of the z edges between `above` and `below` and of the x and y edges in the plane of
    /// `above` (its cubes above: layerAbove, below: layerBelow), each split in two triangles:
    /// those of the edges that start at a sample the tile owns.
    void emitQuads() {
        const int ljLo = own.j0 - sy0, ljHi = std::min(own.j1, Q - 1) - sy0;
        const int liLo = own.i0 - sx0, liHi = std::min(own.i1, P - 1) - sx0;
        tbb::parallel_for(ljLo, ljHi, [&](int lj) {
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
            for (int li = liLo; li < liHi; ++li) {
                if ((li - liLo) % 8 == 0 && li + 8 <= liHi) {
                    const size_t s = sample(li, lj);
                    if (noEdge8(&above.in[s], &below.in[s], W)) {
                        li += 7;  // eight samples without a crossing edge: no quad
                        continue;
                    }
                }
                const int pi = sx0 + li;
                const size_t s = sample(li, lj);
                const bool realColumn = pi >= 1 && pi <= nx;
                if (realRow && realColumn && above.in[s] != below.in[s])  // z edge
                    quad(layerBelow[cube(li - 1, lj - 1)], layerBelow[cube(li, lj - 1)],
                         layerBelow[cube(li, lj)], layerBelow[cube(li - 1, lj)],
                         !(below.in[s] && !above.in[s]));
                if (realRow && above.in[s] != above.in[s + 1])  // x edge (pi, pi + 1)
                    quad(layerBelow[cube(li, lj - 1)], layerBelow[cube(li, lj)],
                         layerAbove[cube(li, lj)], layerAbove[cube(li, lj - 1)],
                         !(above.in[s] && !above.in[s + 1]));
                if (realColumn && above.in[s] != above.in[s + W])  // y edge (pj, pj + 1)
                    quad(layerBelow[cube(li - 1, lj)], layerAbove[cube(li - 1, lj)],
                         layerAbove[cube(li, lj)], layerBelow[cube(li, lj)],
                         !(above.in[s] && !above.in[s + W]));
            }
            rowVolume[lj] = moment;
        });
        for (int lj = ljLo; lj < ljHi; ++lj) {
            tileVolume += rowVolume[lj] / 6.0;
            write(rowTriangles[lj]);
        }
    }

    void write(const std::vector<std::array<uint32_t, 3>>& triangles) {
        triangleCount += triangles.size();
        if (keep) kept.insert(kept.end(), triangles.begin(), triangles.end());
        if (!stlOut) return;
        buffer.resize(triangles.size() * 50);
        char* p = buffer.data();
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
        stlOut->write(buffer.data(), std::streamsize(buffer.size()));
    }

    void advance(const exposure::SurfaceGrid* values, double z) {
        if (!started) {
            load(above, nullptr, z + voxelHeight);
            if (!referenceSet) reference = position(0, 0, z);
            referenceSet = true;
            started = true;
        }
        load(below, values, z);
        buildLayer();
        emitQuads();
        std::swap(above, below);
        std::swap(layerAbove, layerBelow);
        std::swap(filledAbove, filledBelow);
        ++step;
    }
};

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

StreamingCuredSurface::~StreamingCuredSurface() = default;

void StreamingCuredSurface::add(const exposure::ExposureSlice& slice) {
    State& s = *mState;
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
    s.advance(&values, slice.z);
}

void StreamingCuredSurface::finish() {
    State& s = *mState;
    if (s.finished) return;
    if (s.started) s.closeTile();
    s.finished = true;
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
    return mState->triangleCount;
}
double StreamingCuredSurface::volume() const {
    return mState->volume;
}
const std::vector<glm::vec3>& StreamingCuredSurface::vertices() const {
    return mState->vertices;
}
const std::vector<float>& StreamingCuredSurface::deviations() const {
    return mState->deviations;
}
const DeviationStatistics& StreamingCuredSurface::statistics() const {
    return mState->statistics;
}
void StreamingCuredSurface::keepTriangles(bool keep) {
    mState->keep = keep;
}

nlohmann::json StreamingCuredSurface::saveState() {
    State& s = *mState;
    if (s.keep || s.stl || s.finished)
        throw InputError(
            "the cured surface's state is saved only for an in-place STL, without "
            "kept triangles, before finish()");
    if (s.started) s.closeTile();
    uint64_t stlBytes = 0;
    if (s.stlOut) {
        s.stlOut->flush();
        if (!*s.stlOut) throw InputError("cannot write the cured surface", s.inPlacePath);
        stlBytes = uint64_t(s.stlOut->tellp());
    }
    return {{"triangles", s.triangleCount},
            {"volume", s.volume},
            {"reference", {s.reference.x, s.reference.y, s.reference.z}},
            {"reference_set", s.referenceSet},
            {"statistics", s.statistics.toJson()},
            {"stl_bytes", stlBytes}};
}

void StreamingCuredSurface::restoreState(const nlohmann::json& state) {
    State& s = *mState;
    if (s.started || s.triangleCount || s.stl)
        throw InputError("the cured surface's state is restored only before its first slice");
    try {
        s.triangleCount = state.at("triangles").get<uint64_t>();
        s.volume = state.at("volume").get<double>();
        const auto& r = state.at("reference");
        s.reference = {r.at(0).get<double>(), r.at(1).get<double>(), r.at(2).get<double>()};
        s.referenceSet = state.at("reference_set").get<bool>();
        s.statistics = DeviationStatistics::fromJson(state.at("statistics"));
        s.tileStatistics = DeviationStatistics(s.statistics.band());
        const uint64_t stlBytes = state.at("stl_bytes").get<uint64_t>();
        if (s.inPlacePath.empty() != (stlBytes == 0))
            throw InputError("the saved cured surface's STL does not match this one's");
        if (stlBytes == 0) return;
        // The tiles after the state's are written again: the STL is cut back to its length.
        std::error_code error;
        const auto size = std::filesystem::file_size(s.inPlacePath, error);
        if (error || size < stlBytes)
            throw InputError(
                "shorter than its saved state (" + std::to_string(stlBytes) + " bytes)",
                s.inPlacePath);
        std::filesystem::resize_file(s.inPlacePath, stlBytes);
        s.inPlace = std::make_unique<std::fstream>(s.inPlacePath,
                                                   std::ios::in | std::ios::out | std::ios::binary);
        s.inPlace->seekp(0, std::ios::end);
        if (!*s.inPlace) throw InputError("cannot write the cured surface", s.inPlacePath);
        s.stlOut = s.inPlace.get();
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed cured-surface state: ") + e.what());
    }
}

void StreamingCuredSurface::mergeState(const nlohmann::json& later, const std::string& stlBody) {
    State& s = *mState;
    if (s.started || s.keep || s.finished)
        throw InputError("the cured surface merges other tiles only between its own");
    try {
        s.triangleCount += later.at("triangles").get<uint64_t>();
        s.volume += later.at("volume").get<double>();
        s.statistics.merge(DeviationStatistics::fromJson(later.at("statistics")));
        if (!s.referenceSet) {
            const auto& r = later.at("reference");
            s.reference = {r.at(0).get<double>(), r.at(1).get<double>(), r.at(2).get<double>()};
            s.referenceSet = later.at("reference_set").get<bool>();
        }
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed cured-surface state: ") + e.what());
    }
    s.openInPlace();
    if (s.stlOut) s.stlOut->write(stlBody.data(), std::streamsize(stlBody.size()));
}

geometry::Mesh StreamingCuredSurface::mesh() const {
    const State& s = *mState;
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
