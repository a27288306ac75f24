// What MPI ranks do with the pictures of a tiled run (pipeline/cluster_run.h): each tile
// recorded alone into a fresh recorder, its share saved (savePartial) and merged in the tiles'
// order (mergePartial) gives the recorder fed every tile in turn, to the bit: the 3D view's layer
// sections (pixel sums over cells of several tiles, so the order of the additions shows) and the
// figures' x-z section and x-y map.
#include <catch2/catch.hpp>

#include <filesystem>

#include "vpsim/core/binary_state.h"
#include "vpsim/core/io.h"
#include "vpsim/cure/threshold_law.h"
#include "vpsim/geometry/test_parts.h"
#include "vpsim/report/figures.h"
#include "vpsim/report/layer_sections.h"

using namespace vpsim;

namespace {

/// A recorder's saved state as bytes.
template <class Recorder>
std::string stateBytes(const Recorder& recorder, const std::string& file) {
    BinaryStateWriter out(file);
    recorder.saveState(out);
    out.commit();
    return readFile(file);
}

}  // namespace

TEST_CASE("pictures of tiles recorded apart and merged in order are one recorder's", "[report]") {
    exposure::ExposureGrid grid;
    grid.nx = 300, grid.ny = 121;  // 2 x 2 cells per section pixel: seams cut pixels
    grid.originX = -1.5, grid.originY = -0.6, grid.pitch = 0.01, grid.slicesPerLayer = 3;
    geometry::TestPartOptions options;
    options.size = 2.0;
    options.height = 0.2;
    const geometry::Mesh part = geometry::makeTestPart("box", options);
    geometry::LayerStack stack;
    stack.layerThickness = 0.05;
    const int layers = 4;
    for (int k = 0; k < layers; ++k) {
        geometry::Layer layer;
        layer.index = k;
        layer.z = 0.05 * k + 0.025;
        layer.region = geometry::PolygonSet::rectangle({-1.0, -0.5}, {1.0, 0.5});
        stack.layers.push_back(layer);
    }
    const cure::ThresholdLaw law(0.1);
    // Values with many significant bits, around the critical dose.
    auto value = [](int i, int j, int k, int s) {
        const uint32_t h =
            uint32_t(i) * 73856093u ^ uint32_t(j) * 19349663u ^ uint32_t(4 * k + s) * 83492791u;
        return float(0.05 + 0.1 * double(h % 100003) / 100003.0);
    };
    const std::vector<exposure::CellWindow> cores = {
        {0, 0, 151, 61}, {151, 0, 300, 61}, {0, 61, 151, 121}, {151, 61, 300, 121}};
    const int totalSlices = layers * grid.slicesPerLayer, row = 70, mapLayer = 1;
    auto feedTile = [&](const exposure::CellWindow& core, auto&... recorders) {
        for (int k = layers - 1; k >= 0; --k)
            for (int s = 0; s < grid.slicesPerLayer; ++s) {
                exposure::SurfaceGrid g = grid.surface();
                for (int j = 0; j < grid.ny; ++j)
                    for (int i = 0; i < grid.nx; ++i) g.at(i, j) = value(i, j, k, s);
                const exposure::ExposureSlice slice(k, s, 0.05 * (k + 1) - (s + 0.5) * 0.05 / 3, &g,
                                                    core);
                (recorders.add(slice), ...);
            }
    };
    report::LayerSectionRecorder oneLayers(stack, grid, law), mergedLayers(stack, grid, law);
    report::SectionRecorder oneSections(part, grid, totalSlices, law, mapLayer, row),
        mergedSections(part, grid, totalSlices, law, mapLayer, row);
    const std::string file =
        (std::filesystem::temp_directory_path() / "vpsim_picture_partials.bin").string();
    for (const exposure::CellWindow& core : cores) {
        report::LayerSectionRecorder aloneLayers(stack, grid, law);
        report::SectionRecorder aloneSections(part, grid, totalSlices, law, mapLayer, row);
        feedTile(core, oneLayers, oneSections, aloneLayers, aloneSections);
        {
            BinaryStateWriter out(file);
            aloneLayers.savePartial(out, core);
            aloneSections.savePartial(out, core);
            out.commit();
        }
        const BinaryStateReader in(file);
        mergedLayers.mergePartial(in, core);
        mergedSections.mergePartial(in, core);
    }
    const std::string a = file + ".a", b = file + ".b";
    CHECK(stateBytes(mergedLayers, a) == stateBytes(oneLayers, b));
    CHECK(stateBytes(mergedSections, a) == stateBytes(oneSections, b));
    // A share of another tile's window is refused, naming the file.
    report::LayerSectionRecorder other(stack, grid, law);
    CHECK_THROWS_WITH(other.mergePartial(BinaryStateReader(file), cores[0]),
                      Catch::Contains("vpsim_picture_partials.bin"));
    for (const std::string& f : {file, a, b}) std::filesystem::remove(f);
}
