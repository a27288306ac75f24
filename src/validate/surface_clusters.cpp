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

uint32_t SurfaceClusters::find(const Key& key, const glm::dvec3& first) {
    // Looked up before inserting: emplace would make (and free) a node for every known cell.
    const auto it = mIndex.find(key);
    if (it != mIndex.end()) return it->second;
    const auto index = uint32_t(mClusters.size());
    mIndex.emplace(key, index);
    mClusters.emplace_back();
    mClusters.back().first = first;
    mTile.emplace_back();
    return index;
}

uint32_t SurfaceClusters::add(const glm::dvec3& p, float value, bool owned) {
    const Key key = keyOf(p);
    if (mLast == UINT32_MAX || !(key == mLastKey)) {
        mLast = find(key, p);
        mLastKey = key;
    }
    if (owned) {
        TileSum& t = mTile[mLast];
        if (t.count == 0) mTouched.push_back(mLast);
        t.sum += p;
        t.valueSum += value;
        ++t.count;
    }
    return mLast;
}

void SurfaceClusters::endTile() {
    for (uint32_t c : mTouched) {
        Cluster& cluster = mClusters[c];
        TileSum& t = mTile[c];
        cluster.sum += t.sum;
        cluster.valueSum += t.valueSum;
        cluster.count += t.count;
        t = TileSum{};
    }
    mTouched.clear();
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

void SurfaceClusters::readChecked(const BinaryStateReader& in, const std::string& prefix,
                                  double cell, std::vector<Cluster>& clusters,
                                  std::vector<std::array<uint32_t, 3>>& triangles) {
    if (in.take<double>(prefix + ".cell") != std::vector<double>{cell})
        throw InputError("malformed checkpoint state (the picture's cell is not this run's)",
                         in.path());
    clusters = in.take<Cluster>(prefix + ".clusters");
    triangles = in.take<std::array<uint32_t, 3>>(prefix + ".triangles");
    // Each cluster's cell from its first position: only finite positions of cells an int64
    // holds (a cut or edited file may hold anything).
    const double limit = 0x1p62 * cell;
    for (const Cluster& c : clusters)
        for (int axis = 0; axis < 3; ++axis)
            if (!(std::abs(c.first[axis]) < limit) || !std::isfinite(c.sum[axis]) ||
                !std::isfinite(c.valueSum))
                throw InputError("malformed checkpoint state (a cluster's position is not finite)",
                                 in.path());
    for (const auto& tri : triangles)
        for (uint32_t v : tri)
            if (v >= clusters.size())
                throw InputError("malformed checkpoint state (a triangle's cluster is missing)",
                                 in.path());
}

void SurfaceClusters::restore(const BinaryStateReader& in, const std::string& prefix) {
    readChecked(in, prefix, mCell, mClusters, mTriangles);
    mIndex.clear();
    for (size_t c = 0; c < mClusters.size(); ++c) {
        if (!mIndex.emplace(keyOf(mClusters[c].first), uint32_t(c)).second)
            throw InputError("malformed checkpoint state (two clusters in one cell)", in.path());
    }
    mTile.assign(mClusters.size(), TileSum{});
    mTouched.clear();
    mLast = UINT32_MAX;
}

void SurfaceClusters::merge(const BinaryStateReader& in, const std::string& prefix) {
    std::vector<Cluster> clusters;
    std::vector<std::array<uint32_t, 3>> triangles;
    readChecked(in, prefix, mCell, clusters, triangles);
    endTile();
    // The later picture's clusters in the order it made them: a cell new here is made in the
    // order the one process would have made it; every cluster's sums are that tile's, added.
    std::vector<uint32_t> index(clusters.size());
    std::unordered_map<Key, bool, KeyHash> seen;  // a cell twice would merge two clusters
    for (size_t c = 0; c < clusters.size(); ++c) {
        const Key key = keyOf(clusters[c].first);
        if (!seen.emplace(key, true).second)
            throw InputError("malformed checkpoint state (two clusters in one cell)", in.path());
        index[c] = find(key, clusters[c].first);
        Cluster& to = mClusters[index[c]];
        to.sum += clusters[c].sum;
        to.valueSum += clusters[c].valueSum;
        to.count += clusters[c].count;
    }
    for (const auto& tri : triangles) addTriangle(index[tri[0]], index[tri[1]], index[tri[2]]);
    mLast = UINT32_MAX;
}

std::vector<float> SurfaceClusters::values() const {
    std::vector<float> out;
    out.reserve(mClusters.size());
    for (const Cluster& c : mClusters) out.push_back(c.count ? float(c.valueSum / c.count) : 0.0f);
    return out;
}

}  // namespace vpsim::validate
