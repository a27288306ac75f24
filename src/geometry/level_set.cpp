#include "vpsim/geometry/level_set.h"

#include <atomic>
#include <cmath>
#include <mutex>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/vdb_file.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/log.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"

namespace vpsim::geometry {

struct LevelSet::Impl {
    openvdb::FloatGrid::Ptr grid;
};

namespace {

/// Shows OpenVDB's progress reports through vpsim's Progress (wasInterrupted is called from
/// worker threads, with a percentage when OpenVDB knows one). Never interrupts.
class ProgressInterrupter : public openvdb::util::NullInterrupter {
public:
    explicit ProgressInterrupter(Progress& progress) : mProgress(progress) {}
    bool wasInterrupted(int percent) override {
        int last = mLast.load();
        while (percent > last && !mLast.compare_exchange_weak(last, percent)) {}
        mProgress.advance(percent > last ? uint64_t(percent - last) : 0);
        return false;
    }

private:
    Progress& mProgress;
    std::atomic<int> mLast{0};
};

}  // namespace

LevelSet::LevelSet(std::unique_ptr<Impl> impl) : mImpl(std::move(impl)) {}
LevelSet::LevelSet(LevelSet&&) noexcept = default;
LevelSet& LevelSet::operator=(LevelSet&&) noexcept = default;
LevelSet::~LevelSet() = default;

double LevelSet::estimateBytes(const Mesh& mesh, const LevelSetOptions& options) {
    // Band voxels ~ area / h^2 * 2 * halfWidth; meshToVolume keeps a float distance and an int32
    // closest-primitive index per voxel plus leaf-node overhead and partial leaves (~4x).
    const double h = options.voxelSize;
    const double bandVoxels = mesh.area() / (h * h) * 2.0 * (options.halfWidthVoxels + 1.0);
    return bandVoxels * 8.0 * 4.0 + double(mesh.triangles.size()) * 64.0;
}

LevelSet LevelSet::fromMesh(const Mesh& mesh, const LevelSetOptions& options) {
    if (!(options.voxelSize > 0.0) || !std::isfinite(options.voxelSize)) {
        throw InputError("level-set voxel size must be positive, got " +
                         formatQuantity(options.voxelSize) + " mm");
    }
    if (!(options.halfWidthVoxels >= 1.0)) {
        throw InputError("level-set half-width must be at least 1 voxel, got " +
                         formatQuantity(options.halfWidthVoxels));
    }
    if (mesh.triangles.empty()) throw InputError("cannot build a level set of an empty mesh");
    const double bytes = estimateBytes(mesh, options);
    if (bytes > options.maxBytes) {
        throw ResourceError("level set at voxel size " +
                            formatQuantity(options.voxelSize * 1000.0) + " um would need about " +
                            formatBytes(bytes) + " (limit " + formatBytes(options.maxBytes) +
                            "): use a larger voxel size");
    }
    vdb::initialise();
    std::vector<openvdb::Vec3s> points;
    points.reserve(mesh.vertices.size());
    for (const auto& v : mesh.vertices) points.emplace_back(float(v.x), float(v.y), float(v.z));
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
    const auto xform = openvdb::math::Transform::createLinearTransform(options.voxelSize);
    auto impl = std::make_unique<Impl>();
    Progress progress("level set of the part (percent)", 100);
    ProgressInterrupter interrupter(progress);
    // Passing the NullInterrupter base uses OpenVDB's explicit instantiation (no template bloat).
    impl->grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(
        interrupter.interrupter(), *xform, points, triangles, float(options.halfWidthVoxels));
    if (progress.done() < 100) progress.advance(100 - progress.done());  // OpenVDB stops at 99
    impl->grid->setName("part");
    logDebug("level set: " + std::to_string(impl->grid->activeVoxelCount()) + " active voxels, " +
             formatBytes(double(impl->grid->memUsage())));
    return LevelSet(std::move(impl));
}

LevelSet LevelSet::load(const std::string& path) {
    vdb::initialise();
    try {
        openvdb::io::File file(path);
        file.open();
        openvdb::GridBase::Ptr base;
        for (auto it = file.beginName(); it != file.endName() && !base; ++it) {
            openvdb::GridBase::Ptr g = file.readGrid(it.gridName());
            if (g->isType<openvdb::FloatGrid>()) base = g;
        }
        file.close();
        if (!base) throw InputError("no float grid in the file", path);
        auto impl = std::make_unique<Impl>();
        impl->grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        return LevelSet(std::move(impl));
    } catch (const openvdb::Exception& e) {
        throw InputError(std::string("cannot read VDB: ") + e.what(), path);
    }
}

double LevelSet::signedDistance(const glm::dvec3& p) const {
    openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(
        *mImpl->grid);
    return sampler.wsSample(openvdb::Vec3d(p.x, p.y, p.z));
}

void LevelSet::sample(const std::vector<glm::dvec3>& points, std::vector<float>& out) const {
    out.resize(points.size());
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, points.size(), 4096),
        [&](const tbb::blocked_range<size_t>& r) {
            // One sampler (and its node cache) per chunk: accessors are not shared between threads.
            openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(
                *mImpl->grid);
            for (size_t i = r.begin(); i < r.end(); ++i) {
                out[i] =
                    float(sampler.wsSample(openvdb::Vec3d(points[i].x, points[i].y, points[i].z)));
            }
        });
}

double LevelSet::voxelSize() const {
    return mImpl->grid->voxelSize()[0];
}

double LevelSet::halfWidth() const {
    return mImpl->grid->background();
}

size_t LevelSet::activeVoxelCount() const {
    return size_t(mImpl->grid->activeVoxelCount());
}

size_t LevelSet::memoryBytes() const {
    return size_t(mImpl->grid->memUsage());
}

Bounds LevelSet::activeBounds() const {
    const openvdb::CoordBBox box = mImpl->grid->evalActiveVoxelBoundingBox();
    Bounds b;
    if (box.empty()) return b;
    const openvdb::Vec3d lo = mImpl->grid->indexToWorld(box.min()),
                         hi = mImpl->grid->indexToWorld(box.max());
    b.add({lo.x(), lo.y(), lo.z()});
    b.add({hi.x(), hi.y(), hi.z()});
    return b;
}

void LevelSet::save(const std::string& path) const {
    vdb::writeGrids(path, {mImpl->grid});
}

}  // namespace vpsim::geometry
