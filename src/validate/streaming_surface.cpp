#include "vpsim/validate/streaming_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>

#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/geometry/mesh_distance.h"

namespace vpsim::validate {
namespace {

constexpr uint32_t NONE = UINT32_MAX;

/// A slice padded with one zero cell on every side: (nx + 2) x (ny + 2) values and cured flags.
struct PaddedSlice {
    std::vector<float> value;
    std::vector<uint8_t> in;
    double z = 0;
};

}  // namespace

struct StreamingCuredSurface::State {
    exposure::ExposureGrid grid;
    double voxelHeight, iso, band;
    std::unique_ptr<geometry::MeshDistance> distance;
    std::unique_ptr<AtomicFileStream> stl;
    int nx, ny, P, Q;  ///< grid cells; padded width and height
    PaddedSlice above, below;
    bool started = false, finished = false;
    std::vector<uint32_t> layerAbove, layerBelow;  ///< global vertex per cube, (nx+1) x (ny+1)
    std::vector<glm::vec3> vertices;
    std::vector<float> deviations;
    std::vector<std::vector<std::pair<int, glm::vec3>>> rowVertices;
    std::vector<std::vector<std::array<uint32_t, 3>>> rowTriangles;
    std::vector<double> rowVolume;
    std::vector<std::array<uint32_t, 3>> kept;
    bool keep = false;
    uint64_t triangleCount = 0;
    double volume = 0;
    glm::dvec3 reference{0.0};  ///< volume moments are taken about this point (less rounding)
    std::vector<char> buffer;

    size_t sample(int pi, int pj) const { return size_t(pj) * P + pi; }
    size_t cube(int ci, int cj) const { return size_t(cj) * (nx + 1) + ci; }
    glm::dvec3 position(int pi, int pj, double z) const {
        return {grid.originX + (pi - 0.5) * grid.pitch, grid.originY + (pj - 0.5) * grid.pitch, z};
    }

    void load(PaddedSlice& target, const exposure::SurfaceGrid* values, double z) {
        target.z = z;
        tbb::parallel_for(0, Q, [&](int pj) {
            float* v = &target.value[sample(0, pj)];
            uint8_t* in = &target.in[sample(0, pj)];
            if (!values || pj == 0 || pj == Q - 1) {
                std::fill(v, v + P, 0.0f);
                std::fill(in, in + P, uint8_t(0));
                return;
            }
            const float* row = &values->values[size_t(pj - 1) * nx];
            v[0] = v[P - 1] = 0.0f;
            std::memcpy(v + 1, row, sizeof(float) * nx);
            for (int pi = 0; pi < P; ++pi) in[pi] = double(v[pi]) >= iso;  // CureLaw::isCured
        });
    }

    /// The vertex of cube (ci, cj) between `above` and `below`: the mean of its edge crossings.
    glm::dvec3 cubeVertex(int ci, int cj) const {
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
        for (int s = 0; s < 2; ++s) {
            const PaddedSlice& sl = s == 0 ? above : below;
            for (int dj = 0; dj < 2; ++dj)  // x edges
                edge(sl, sample(ci, cj + dj), sl, sample(ci + 1, cj + dj),
                     position(ci, cj + dj, sl.z), position(ci + 1, cj + dj, sl.z));
            for (int di = 0; di < 2; ++di)  // y edges
                edge(sl, sample(ci + di, cj), sl, sample(ci + di, cj + 1),
                     position(ci + di, cj, sl.z), position(ci + di, cj + 1, sl.z));
        }
        for (int dj = 0; dj < 2; ++dj)  // z edges
            for (int di = 0; di < 2; ++di)
                edge(above, sample(ci + di, cj + dj), below, sample(ci + di, cj + dj),
                     position(ci + di, cj + dj, above.z), position(ci + di, cj + dj, below.z));
        return sum / double(std::max(count, 1));
    }

    /// Vertices of the cubes between `above` and `below` into layerBelow, rows in parallel and
    /// numbered in row order.
    void buildLayer() {
        std::fill(layerBelow.begin(), layerBelow.end(), NONE);
        tbb::parallel_for(0, ny + 1, [&](int cj) {
            auto& out = rowVertices[cj];
            out.clear();
            const uint8_t *a0 = &above.in[sample(0, cj)], *a1 = &above.in[sample(0, cj + 1)],
                          *b0 = &below.in[sample(0, cj)], *b1 = &below.in[sample(0, cj + 1)];
            for (int ci = 0; ci <= nx; ++ci) {
                const int sum = a0[ci] + a0[ci + 1] + a1[ci] + a1[ci + 1] + b0[ci] + b0[ci + 1] +
                                b1[ci] + b1[ci + 1];
                if (sum == 0 || sum == 8) continue;
                out.emplace_back(ci, glm::vec3(cubeVertex(ci, cj)));
            }
        });
        std::vector<size_t> first(ny + 2, vertices.size());
        for (int cj = 0; cj <= ny; ++cj) first[cj + 1] = first[cj] + rowVertices[cj].size();
        vertices.resize(first[ny + 1]);
        deviations.resize(first[ny + 1]);
        tbb::parallel_for(0, ny + 1, [&](int cj) {
            size_t v = first[cj];
            for (const auto& [ci, p] : rowVertices[cj]) {
                vertices[v] = p;
                deviations[v] =
                    distance
                        ? float(std::clamp(distance->signedDistance(glm::dvec3(p)), -band, band))
                        : 0.0f;
                layerBelow[cube(ci, cj)] = uint32_t(v);
                ++v;
            }
        });
    }

    /// Quads of the z edges between `above` and `below` and of the x and y edges in the plane of
    /// `above` (its cubes above: layerAbove, below: layerBelow), each split in two triangles.
    void emitQuads() {
        tbb::parallel_for(0, Q - 1, [&](int pj) {
            auto& out = rowTriangles[pj];
            out.clear();
            double moment = 0;
            auto quad = [&](uint32_t q0, uint32_t q1, uint32_t q2, uint32_t q3, bool flip) {
                if (flip) std::swap(q1, q3);
                const std::array<uint32_t, 3> t[2] = {{q0, q1, q2}, {q0, q2, q3}};
                for (const auto& tri : t) {
                    out.push_back(tri);
                    const glm::dvec3 a = glm::dvec3(vertices[tri[0]]) - reference,
                                     b = glm::dvec3(vertices[tri[1]]) - reference,
                                     c = glm::dvec3(vertices[tri[2]]) - reference;
                    moment += glm::dot(a, glm::cross(b, c));
                }
            };
            const bool realRow = pj >= 1 && pj <= ny;
            for (int pi = 0; pi < P - 1; ++pi) {
                const size_t s = sample(pi, pj);
                const bool realColumn = pi >= 1 && pi <= nx;
                if (realRow && realColumn && above.in[s] != below.in[s])  // z edge
                    quad(layerBelow[cube(pi - 1, pj - 1)], layerBelow[cube(pi, pj - 1)],
                         layerBelow[cube(pi, pj)], layerBelow[cube(pi - 1, pj)],
                         !(below.in[s] && !above.in[s]));
                if (realRow && above.in[s] != above.in[s + 1])  // x edge (pi, pi + 1)
                    quad(layerBelow[cube(pi, pj - 1)], layerBelow[cube(pi, pj)],
                         layerAbove[cube(pi, pj)], layerAbove[cube(pi, pj - 1)],
                         !(above.in[s] && !above.in[s + 1]));
                if (realColumn && above.in[s] != above.in[s + P])  // y edge (pj, pj + 1)
                    quad(layerBelow[cube(pi - 1, pj)], layerAbove[cube(pi - 1, pj)],
                         layerAbove[cube(pi, pj)], layerBelow[cube(pi, pj)],
                         !(above.in[s] && !above.in[s + P]));
            }
            rowVolume[pj] = moment;
        });
        for (int pj = 0; pj < Q - 1; ++pj) {
            volume += rowVolume[pj] / 6.0;
            write(rowTriangles[pj]);
        }
    }

    void write(const std::vector<std::array<uint32_t, 3>>& triangles) {
        triangleCount += triangles.size();
        if (keep) kept.insert(kept.end(), triangles.begin(), triangles.end());
        if (!stl) return;
        buffer.resize(triangles.size() * 50);
        char* p = buffer.data();
        for (const auto& tri : triangles) {
            const glm::vec3 &a = vertices[tri[0]], &b = vertices[tri[1]], &c = vertices[tri[2]];
            glm::vec3 n = glm::cross(b - a, c - a);
            const float length = glm::length(n);
            n = length > 0 ? n / length : glm::vec3(0.0f);
            const float f[12] = {n.x, n.y, n.z, a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
            std::memcpy(p, f, sizeof f);
            std::memset(p + 48, 0, 2);
            p += 50;
        }
        stl->stream().write(buffer.data(), std::streamsize(buffer.size()));
    }

    void step(const exposure::SurfaceGrid* values, double z) {
        if (!started) {
            load(above, nullptr, z + voxelHeight);
            reference = position(0, 0, z);
            started = true;
        }
        load(below, values, z);
        buildLayer();
        emitQuads();
        std::swap(above, below);
        std::swap(layerAbove, layerBelow);
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
    s.band = band;
    s.nx = grid.nx;
    s.ny = grid.ny;
    s.P = grid.nx + 2;
    s.Q = grid.ny + 2;
    for (PaddedSlice* slice : {&s.above, &s.below}) {
        slice->value.assign(size_t(s.P) * s.Q, 0.0f);
        slice->in.assign(size_t(s.P) * s.Q, 0);
    }
    s.layerAbove.assign(size_t(s.nx + 1) * (s.ny + 1), NONE);
    s.layerBelow = s.layerAbove;
    s.rowVertices.resize(s.ny + 1);
    s.rowTriangles.resize(s.Q);
    s.rowVolume.assign(s.Q, 0.0);
    if (part) s.distance = std::make_unique<geometry::MeshDistance>(*part);
    if (!stlPath.empty()) {
        s.stl = std::make_unique<AtomicFileStream>(stlPath);
        char header[84] = {};
        const std::string text = "vpsim binary STL, mm: cured";
        std::memcpy(header, text.data(), text.size());
        s.stl->stream().write(header, 84);
    }
}

StreamingCuredSurface::~StreamingCuredSurface() = default;

void StreamingCuredSurface::add(const exposure::ExposureSlice& slice) {
    State& s = *mState;
    if (s.finished) throw InputError("the cured surface was already finished");
    if (slice.values->nx != s.nx || slice.values->ny != s.ny)
        throw ResourceError("exposure slice does not match the cured-surface grid");
    s.step(slice.values, slice.z);
}

void StreamingCuredSurface::finish() {
    State& s = *mState;
    if (s.finished) return;
    if (s.started) s.step(nullptr, s.above.z - s.voxelHeight);
    s.finished = true;
    if (s.triangleCount == 0)
        throw InputError("nothing cured: the exposure never reaches the critical dose (" +
                         formatQuantity(s.iso * 100.0) + " mJ/cm^2)");
    if (s.stl) {
        if (s.triangleCount > UINT32_MAX)
            throw InputError("too many triangles for a binary STL", s.stl->path());
        const uint32_t count = uint32_t(s.triangleCount);
        s.stl->stream().seekp(80);
        s.stl->stream().write(reinterpret_cast<const char*>(&count), 4);
        s.stl->commit();
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
void StreamingCuredSurface::keepTriangles(bool keep) {
    mState->keep = keep;
}

geometry::Mesh StreamingCuredSurface::mesh() const {
    geometry::Mesh mesh;
    mesh.vertices.reserve(mState->vertices.size());
    for (const auto& v : mState->vertices) mesh.vertices.emplace_back(v);
    mesh.triangles = mState->kept;
    return mesh;
}

}  // namespace vpsim::validate
