#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "vpsim/cure/threshold_law.h"
#include "vpsim/exposure/dose_volume.h"
#include "vpsim/validate/cured_surface.h"
#include "vpsim/validate/slice_validator.h"
#include "vpsim/validate/surface_deviation.h"

using namespace vpsim;

namespace {

/// Closed box mesh with outward normals.
geometry::Mesh box(glm::dvec3 lo, glm::dvec3 hi) {
    geometry::Mesh mesh;
    for (int k = 0; k < 8; ++k)
        mesh.vertices.push_back({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        mesh.triangles.push_back({f[0], f[1], f[2]});
        mesh.triangles.push_back({f[0], f[2], f[3]});
    }
    return mesh;
}

/// Feeds the validator synthetic slices, top down: dose 2 Ec inside `cured`, 0 elsewhere.
validate::SliceValidationSummary validateSynthetic(const geometry::Mesh& reference, glm::dvec3 lo,
                                                   glm::dvec3 hi,
                                                   const exposure::ExposureGrid& grid, double dz,
                                                   int slices) {
    const cure::ThresholdLaw law(1.0);  // Ec = 1
    validate::SliceValidator validator(reference, grid, law, dz);
    exposure::SurfaceGrid values(grid.nx, grid.ny, grid.originX, grid.originY, grid.pitch);
    for (int k = slices - 1; k >= 0; --k) {
        double z = (k + 0.5) * dz;
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i) {
                double x = values.centreX(i), y = values.centreY(j);
                bool inside = x > lo.x && x < hi.x && y > lo.y && y < hi.y && z > lo.z && z < hi.z;
                values.at(i, j) = inside ? float(2 * law.criticalDose()) : 0.0f;
            }
        validator.add({k / grid.slicesPerLayer, grid.slicesPerLayer - 1 - k % grid.slicesPerLayer,
                       z, &values});
    }
    return validator.summary();
}

}  // namespace

// A reference block floating at z in [0.5, 1.0] (its underside is down-facing) and a cured block
// grown by 0.1 mm in x and y and reaching 0.2 mm lower. Cell edges coincide with the box faces,
// so the voxel answers are exact up to float rounding: IoU = 0.5 / (1.44 * 0.7), over-cure 0.2 mm,
// XY error = (1.44 - 1) / 4 mm.
TEST_CASE("validation metrics of a grown and lowered block are exact", "[validate]") {
    geometry::Mesh reference = box({0, 0, 0.5}, {1, 1, 1.0});
    exposure::ExposureGrid grid = exposure::ExposureGrid::covering(0, 0, 1, 1, 0.2, 0.05, 2);
    auto summary = validateSynthetic(reference, {-0.1, -0.1, 0.3}, {1.1, 1.1, 1.0}, grid, 0.05, 20);
    CHECK(summary.iou == Approx(0.5 / (1.44 * 0.7)).epsilon(1e-9));
    CHECK(summary.referenceVolume == Approx(0.5).epsilon(1e-9));
    CHECK(summary.curedVolume == Approx(1.44 * 0.7).epsilon(1e-9));
    CHECK(summary.overcureBelowDownFacingMax == Approx(0.2).epsilon(1e-6));
    CHECK(summary.overcureBelowDownFacingMean == Approx(0.2).epsilon(1e-6));
    CHECK(summary.overcureBelowDownFacingMedian == Approx(0.2).epsilon(1e-6));
    CHECK(summary.downFacingColumns == 400);
    CHECK(summary.xyContourErrorMax == Approx(0.44 / 4).epsilon(1e-9));
    REQUIRE(summary.layers.size() == 10);
    CHECK(summary.layers.front().layer == 0);
    CHECK(summary.layers[3].referenceArea == 0.0);  // z < 0.5: below the floating block
}

TEST_CASE("a perfect cure validates as perfect", "[validate]") {
    geometry::Mesh reference = box({0, 0, 0.0}, {1, 1, 0.5});
    exposure::ExposureGrid grid = exposure::ExposureGrid::covering(0, 0, 1, 1, 0.1, 0.05, 1);
    auto summary = validateSynthetic(reference, {0, 0, 0}, {1, 1, 0.5}, grid, 0.05, 10);
    CHECK(summary.iou == Approx(1.0));
    CHECK(summary.overcureBelowDownFacingMax == 0.0);
    CHECK(summary.xyContourErrorMax == 0.0);
}

// Surface deviation of a block grown by g = 0.05 mm on every side: its 8 corners lie sqrt(3) g
// from the reference corners. Trilinear interpolation of an exact distance grid at 0.01 mm voxels
// is accurate to about a tenth of a voxel near a corner: 2e-3 mm.
TEST_CASE("surface deviation of a grown block", "[validate]") {
    geometry::Mesh reference = box({0, 0, 0}, {1, 1, 1});
    geometry::LevelSetOptions options;
    options.voxelSize = 0.01;
    options.halfWidthVoxels = 12;
    auto levelSet = geometry::LevelSet::fromMesh(reference, options);
    const double g = 0.05;
    auto deviation =
        validate::measureSurfaceDeviation(box({-g, -g, -g}, {1 + g, 1 + g, 1 + g}), levelSet);
    CHECK(deviation.samples == 8);
    CHECK(deviation.mean == Approx(std::sqrt(3.0) * g).margin(2e-3));
    CHECK(deviation.max == Approx(std::sqrt(3.0) * g).margin(2e-3));
    CHECK(deviation.beyondBand == 0);
}

// The cured iso-surface of a dose field that is 2 Ec inside a block and 0 outside lies halfway
// between voxel centres, i.e. on the block faces when they lie on voxel boundaries: its volume
// equals the block's to the triangulation's accuracy (1%).
TEST_CASE("the cured iso-surface encloses the cured voxels", "[validate][vdb]") {
    exposure::ExposureGrid grid = exposure::ExposureGrid::covering(0, 0, 1, 1, 0.1, 0.02, 1);
    exposure::DoseVolume volume(grid, 0.02, 0.0, 0.01f);
    exposure::SurfaceGrid values(grid.nx, grid.ny, grid.originX, grid.originY, grid.pitch);
    for (int k = 29; k >= 0; --k) {
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i) {
                double x = values.centreX(i), y = values.centreY(j), z = (k + 0.5) * 0.02;
                values.at(i, j) =
                    (x > 0.2 && x < 0.8 && y > 0.2 && y < 0.6 && z > 0.1 && z < 0.5) ? 2.0f : 0.0f;
            }
        volume.add({k, 0, (k + 0.5) * 0.02, &values});
    }
    geometry::Mesh cured = validate::curedSurface(volume, cure::ThresholdLaw(1.0));
    REQUIRE(!cured.triangles.empty());
    CHECK(cured.volume() == Approx(0.6 * 0.4 * 0.4).epsilon(0.01));
}

// The validator against a brute force over every voxel, on a random exposure around Ec (runs of
// over-cure that open, grow and close anywhere, rows not a multiple of 8 cells long): the counts,
// the maximum and the over-cure runs must agree exactly, whatever shortcuts add() takes.
TEST_CASE("slice validation equals a brute force over every voxel", "[validate]") {
    const glm::dvec3 lo{0.113, 0.207, 0.31}, hi{0.871, 0.794, 0.77};
    const geometry::Mesh reference = box(lo, hi);
    const exposure::ExposureGrid grid = exposure::ExposureGrid::covering(0, 0, 1, 1, 0.07, 0.03, 3);
    const double dz = 0.04;
    const int slices = 24;
    const cure::ThresholdLaw law(1.0);
    validate::SliceValidator validator(reference, grid, law, dz);
    exposure::SurfaceGrid values(grid.nx, grid.ny, grid.originX, grid.originY, grid.pitch);
    std::mt19937 random(11);
    std::uniform_real_distribution<float> dose(0.0f, 1.6f);
    const size_t cells = size_t(grid.nx) * grid.ny;
    std::vector<uint8_t> above(cells, 0), inRun(cells, 0);
    std::vector<float> run(cells, 0.0f), runs;
    uint64_t inter = 0, unionCount = 0, cured = 0, exposed = 0;
    long downFacing = 0;
    float maxDose = 0;
    for (int k = slices - 1; k >= 0; --k) {
        const double z = (k + 0.5) * dz;
        for (size_t c = 0; c < cells; ++c) {
            // Columns mostly cured or mostly not, so runs last several slices.
            const float bias = (c * 2654435761u) % 3 == 0 ? 0.5f : 0.0f;
            values.values[c] = std::min(dose(random) + bias, 2.0f);
        }
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i) {
                const size_t c = size_t(j) * grid.nx + i;
                const double x = values.centreX(i), y = values.centreY(j);
                const bool r = x > lo.x && x < hi.x && y > lo.y && y < hi.y && z > lo.z && z < hi.z;
                const float d = values.values[c];
                const bool cu = law.isCured(d);
                maxDose = std::max(maxDose, d);
                exposed += d > float(0.02 * law.criticalDose());
                inter += r && cu;
                unionCount += r || cu;
                cured += cu;
                if (r) {
                    if (inRun[c]) runs.push_back(run[c]);
                    inRun[c] = 0, run[c] = 0;
                } else {
                    if (above[c]) ++downFacing, inRun[c] = 1, run[c] = 0;
                    if (inRun[c] && cu) run[c] += float(dz);
                    if (inRun[c] && !cu) runs.push_back(run[c]), inRun[c] = 0, run[c] = 0;
                }
                above[c] = r;
            }
        validator.add({k / grid.slicesPerLayer, grid.slicesPerLayer - 1 - k % grid.slicesPerLayer,
                       z, &values});
    }
    for (size_t c = 0; c < cells; ++c)
        if (inRun[c]) runs.push_back(run[c]);
    const validate::SliceValidationSummary s = validator.summary();
    REQUIRE(!runs.empty());
    std::sort(runs.begin(), runs.end());
    double sum = 0;
    for (float r : runs) sum += r;
    CHECK(s.iou == double(inter) / double(unionCount));
    CHECK(s.curedVolume == double(cured) * grid.pitch * grid.pitch * dz);
    CHECK(s.maxDose == double(maxDose));
    CHECK(s.exposedVoxels == exposed);
    CHECK(s.downFacingColumns == downFacing);
    CHECK(s.overcureBelowDownFacingMean == sum / double(runs.size()));
    CHECK(s.overcureBelowDownFacingMax == runs.back());
    CHECK(s.overcureBelowDownFacingMedian == runs[runs.size() / 2]);
}
