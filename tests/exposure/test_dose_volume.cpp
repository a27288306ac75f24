#include <catch2/catch.hpp>

#include <filesystem>

#include "vpsim/exposure/dose_volume.h"

using namespace vpsim::exposure;

TEST_CASE("dose volumes store slices sparsely at their voxel indices", "[exposure][vdb]") {
    ExposureGrid grid = ExposureGrid::covering(0, 0, 0.2, 0.1, 0, 0.01, 2);
    DoseVolume volume(grid, 0.025, 0.0, 0.5f);
    SurfaceGrid slice(grid.nx, grid.ny, grid.originX, grid.originY, grid.pitch);
    for (int k = 0; k < 4; ++k) {
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i)
                slice.at(i, j) = i < 10 ? float(k + 1) : 0.1f;  // right half below threshold
        volume.add({k / 2, k % 2, (k + 0.5) * 0.025, &slice});
    }
    CHECK(volume.activeVoxels() == uint64_t(10 * grid.ny * 4));
    CHECK(volume.value(3, 5, 2) == 3.0f);
    CHECK(volume.value(15, 5, 2) == 0.0f);
    CHECK(volume.maxValue() == 4.0f);
    auto path = std::filesystem::temp_directory_path() / "vpsim_dose_volume.vdb";
    volume.write(path.string());
    CHECK(std::filesystem::file_size(path) > 0);
}
