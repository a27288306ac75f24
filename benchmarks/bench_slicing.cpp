// Slicing and reference level set of a ~1,000,000-triangle part (a UV sphere of radius 5 mm made
// in code). Prints JSON: STL write/read+check time, slicing 400 layers of 25 um, level set at
// 20 um, each with peak memory (getrusage ru_maxrss), and in the same run the floor of merely
// reading every triangle's z range once, so slicing is quoted as a multiple of that floor and
// as triangles per second. Target (issue 4): slicing under 10 s.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "vpsim/core/progress.h"
#include "vpsim/geometry/level_set.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/geometry/stl_io.h"

using namespace vpsim::geometry;

namespace {

constexpr double PI = 3.14159265358979323846;

double peakRssMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

/// UV sphere: `rings` latitude bands and `segments` longitudes; 2 segments (rings - 1) triangles.
Mesh makeSphere(double radius, int rings, int segments) {
    Mesh mesh;
    mesh.vertices.emplace_back(0.0, 0.0, -radius);
    for (int r = 1; r < rings; ++r) {
        const double polar = PI * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double azimuth = 2.0 * PI * s / segments;
            mesh.vertices.emplace_back(radius * std::sin(polar) * std::cos(azimuth),
                                       radius * std::sin(polar) * std::sin(azimuth),
                                       -radius * std::cos(polar));
        }
    }
    mesh.vertices.emplace_back(0.0, 0.0, radius);
    const auto ring = [&](int r, int s) {
        return uint32_t(1 + (r - 1) * segments + (s % segments));
    };
    const auto top = uint32_t(mesh.vertices.size() - 1);
    for (int s = 0; s < segments; ++s) {
        mesh.triangles.push_back({0, ring(1, s + 1), ring(1, s)});
        mesh.triangles.push_back({top, ring(rings - 1, s), ring(rings - 1, s + 1)});
        for (int r = 1; r + 1 < rings; ++r) {
            mesh.triangles.push_back({ring(r, s), ring(r, s + 1), ring(r + 1, s + 1)});
            mesh.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r + 1, s)});
        }
    }
    mesh.translate({0.0, 0.0, radius});  // stand on z = 0
    return mesh;
}

template <typename F>
double seconds(F&& f) {
    const auto start = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main() {
    vpsim::Progress::setEnabled(false);
    const double radius = 5.0;
    const Mesh sphere = makeSphere(radius, 500, 1000);
    const double triangles = double(sphere.triangles.size());
    nlohmann::json out{{"benchmark", "slicing"},
                       {"triangles", sphere.triangles.size()},
                       {"threads", tbb::info::default_concurrency()}};

    // Floor: one pass reading every triangle's three vertex z values (what bucketing must do).
    double floorSink = 0.0;
    const double floorTime = seconds([&] {
        for (const auto& t : sphere.triangles) {
            floorSink += std::max(
                {sphere.vertices[t[0]].z, sphere.vertices[t[1]].z, sphere.vertices[t[2]].z});
        }
    });
    out["floor_read_triangles_s"] = floorTime;
    out["floor_checksum"] = floorSink;

    // STL out and in (with all checks), through a temporary file.
    const std::string path =
        (std::filesystem::temp_directory_path() / "vpsim_bench_sphere.stl").string();
    out["stl_write_s"] = seconds([&] { writeStl(path, sphere); });
    Mesh read;
    out["stl_read_and_check_s"] = seconds([&] { read = readStl(path); });
    std::filesystem::remove(path);
    out["stl_read_volume_rel_error"] = std::abs(read.volume() / sphere.volume() - 1.0);
    out["peak_rss_after_stl_MiB"] = peakRssMiB();

    // Slicing: 400 layers of 25 um over the 10 mm sphere.
    SliceOptions options;
    options.layerThickness = 0.025;
    std::vector<Layer> layers;
    const double sliceTime = seconds([&] { layers = sliceMesh(read, options); });
    double worstAreaError = 0.0;  // absolute (mm^2): near the poles relative errors are large
    for (const auto& layer : layers) {
        const double h = layer.z - radius;
        const double circle = PI * (radius * radius - h * h);
        worstAreaError = std::max(worstAreaError, std::abs(layer.region.area() - circle));
    }
    out["layers"] = layers.size();
    out["slice_s"] = sliceTime;
    out["slice_triangles_per_s"] = triangles / sliceTime;
    out["slice_over_floor"] = sliceTime / floorTime;
    out["slice_target_s"] = 10.0;
    out["slice_area_vs_circle_max_abs_error_mm2"] =
        worstAreaError;  // tessellation error of the sphere
    out["peak_rss_after_slice_MiB"] = peakRssMiB();

    // Reference level set at 20 um, half-width 3 voxels.
    LevelSetOptions ls;
    ls.voxelSize = 0.02;
    out["level_set_estimated_MiB"] = LevelSet::estimateBytes(read, ls) / (1 << 20);
    double activeVoxels = 0.0, gridMiB = 0.0, centreDistance = 0.0;
    out["level_set_s"] = seconds([&] {
        const LevelSet set = LevelSet::fromMesh(read, ls);
        activeVoxels = double(set.activeVoxelCount());
        gridMiB = double(set.memoryBytes()) / (1 << 20);
        centreDistance = set.signedDistance({radius + 0.01, 0.0, radius});
    });
    out["level_set_active_voxels"] = activeVoxels;
    out["level_set_grid_MiB"] = gridMiB;
    out["level_set_distance_at_0.01mm_outside"] = centreDistance;
    out["peak_rss_after_level_set_MiB"] = peakRssMiB();
    std::cout << out.dump(2) << std::endl;
    return 0;
}
