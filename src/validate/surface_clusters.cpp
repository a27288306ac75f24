#include "vpsim/validate/surface_clusters.h"

#include <cmath>

#include "vpsim/core/error.h"

namespace vpsim::validate {

SurfaceClusters::SurfaceClusters(double cell) : mCell(cell) {
    if (!(cell > 0)) throw InputError("vertex clustering needs a positive cell");
}

size_t SurfaceClusters::KeyHash::operator()(const Key& k) const {
    uint64_t h = uint64_t(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= uint64_t(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= uint64_t(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return size_t(h ^ (h >> 31));
}

SurfaceClusters::Key SurfaceClusters::keyOf(const glm::dvec3& p) const {
    return {int64_t(std::floor(p.x / mCell)), int64_t(std::floor(p.y / mCell)),
            int64_t(std::floor(p.z / mCell))};
}

uint32_t SurfaceClusters::add(const glm::dvec3& p, float value, bool owned) {
    const Key key = keyOf(p);
    if (mLast == UINT32_MAX || !(key == mLastKey)) {
        auto [it, added] = mIndex.emplace(key, uint32_t(mClusters.size()));
        if (added) {
            mClusters.emplace_back();
            mClusters.back().first = p;
        }
        mLast = it->second;
        mLastKey = key;
    }
    if (owned) {
        Cluster& c = mClusters[mLast];
        c.sum += p;
        c.valueSum += value;
        ++c.count;
    }
    return mLast;
}

void SurfaceClusters::addTriangle(uint32_t a, uint32_t b, uint32_t c) {
    if (a != b && b != c && a != c) mTriangles.push_back({a, b, c});
}

geometry::Mesh SurfaceClusters::mesh() const {
    geometry::Mesh out;
    out.vertices.reserve(mClusters.size());
    for (const Cluster& c : mClusters)
        out.vertices.push_back(c.count ? c.sum / double(c.count) : c.first);
    out.triangles = mTriangles;
    return out;
}

void SurfaceClusters::save(BinaryStateWriter& out, const std::string& prefix) const {
    out.add(prefix + ".cell", std::vector<double>{mCell});
    out.add(prefix + ".clusters", mClusters);
    out.add(prefix + ".triangles", mTriangles);
}

void SurfaceClusters::restore(const BinaryStateReader& in, const std::string& prefix) {
    if (in.take<double>(prefix + ".cell") != std::vector<double>{mCell})
        throw InputError("malformed checkpoint state (the picture's cell is not this run's)",
                         in.path());
    mClusters = in.take<Cluster>(prefix + ".clusters");
    mTriangles = in.take<std::array<uint32_t, 3>>(prefix + ".triangles");
    // Each cluster's cell from its first position: only finite positions of cells an int64
    // holds (a cut or edited file may hold anything).
    const double limit = 0x1p62 * mCell;
    for (const Cluster& c : mClusters)
        for (int axis = 0; axis < 3; ++axis)
            if (!(std::abs(c.first[axis]) < limit) || !std::isfinite(c.sum[axis]) ||
                !std::isfinite(c.valueSum))
                throw InputError("malformed checkpoint state (a cluster's position is not finite)",
                                 in.path());
    mIndex.clear();
    for (size_t c = 0; c < mClusters.size(); ++c) {
        if (!mIndex.emplace(keyOf(mClusters[c].first), uint32_t(c)).second)
            throw InputError("malformed checkpoint state (two clusters in one cell)", in.path());
    }
    for (const auto& tri : mTriangles)
        for (uint32_t v : tri)
            if (v >= mClusters.size())
                throw InputError("malformed checkpoint state (a triangle's cluster is missing)",
                                 in.path());
    mLast = UINT32_MAX;
}

std::vector<float> SurfaceClusters::values() const {
    std::vector<float> out;
    out.reserve(mClusters.size());
    for (const Cluster& c : mClusters) out.push_back(c.count ? float(c.valueSum / c.count) : 0.0f);
    return out;
}

}  // namespace vpsim::validate
