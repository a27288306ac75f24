// `vpsim slice FILE.stl --layer 25um`: slices a part (geometry/slicer.h) and reports each layer's
// area and contours; with --out DIR it also writes pictures of chosen layers: SVG of the polygons,
// anti-aliased coverage PNG, binary mask PNG and a signed-distance heat map.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "vpsim/core/error.h"
#include "vpsim/core/image.h"
#include "vpsim/core/io.h"
#include "vpsim/core/log.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/pipeline/estimate.h"

namespace {

using namespace vpsim;
using namespace vpsim::geometry;

std::string formatCount(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.0f", value);
    return text;
}

struct SliceCliOptions {
    std::string file, layer = "50um", pitch = "10um", zStart, outDir, save;
    double plane = 0.5, scale = 1.0;
    std::vector<int> layers;
    bool json = false;
};

nlohmann::json layerJson(const Layer& layer) {
    return {{"index", layer.index},
            {"z", layer.z},
            {"area", layer.region.area()},
            {"perimeter", layer.region.perimeter()},
            {"outer_contours", layer.region.outerCount()},
            {"holes", layer.region.holeCount()}};
}

/// Layers to draw: the ones asked for, else five spread over the part.
std::vector<int> pictureLayers(const std::vector<int>& asked, int count) {
    if (!asked.empty()) return asked;
    std::vector<int> chosen;
    for (int q = 0; q < 5 && count > 0; ++q)
        chosen.push_back(std::min(count - 1, q * (count - 1) / 4));
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
    return chosen;
}

void writePictures(const std::vector<Layer>& layers, const RasterGrid& grid,
                   const std::string& dir) {
    createDirectories(dir);
    for (const Layer& layer : layers) {
        char stem[64];
        std::snprintf(stem, sizeof stem, "/layer_%05d", layer.index);
        const std::string base = dir + stem;
        writePolygonSvg(
            base + ".svg", layer.region,
            "layer " + std::to_string(layer.index) + " at z = " + formatQuantity(layer.z) + " mm");
        writePngGrey(base + "_coverage.png", grid.width, grid.height,
                     toGreyImage(rasterizeCoverage(layer.region, grid), grid));
        std::vector<uint8_t> mask = rasterizeBinary(layer.region, grid);
        for (auto& v : mask) v = v ? 255 : 0;
        writePngGrey(base + "_mask.png", grid.width, grid.height,
                     flipRows(mask, grid.width, grid.height));
        const double band = 20.0 * grid.pitch;
        const TargetMap target = makeTargetMap(layer.region, grid, band);
        writePng(base + "_distance.png",
                 heatMap(flipRows(target.signedDistance, grid.width, grid.height), grid.width,
                         grid.height, -band, band, {0.0}));
    }
    logInfo("wrote pictures of " + std::to_string(layers.size()) + " layers to " + dir +
            " (pitch " + formatQuantity(grid.pitch * 1000.0) + " um, " +
            std::to_string(grid.width) + " x " + std::to_string(grid.height) + " pixels, origin (" +
            formatQuantity(grid.origin.x) + ", " + formatQuantity(grid.origin.y) + ") mm)");
}

/// Bytes per pixel while one layer's pictures are made: coverage (float) and its grey image,
/// mask and flipped mask, signed distance (float) with its flipped copy, the RGB heat map, and
/// the PNG encoder's row copies.
constexpr double PICTURE_BYTES_PER_PIXEL = 4 + 1 + 1 + 1 + 4 + 4 + 3 + 4;
constexpr double MAX_PICTURE_PIXELS = 16384.0 * 16384.0;

/// Refuses, by bytes and before allocating, pictures too large for memory: the raster's own limit
/// counts pixels (2^31), which at 22 bytes each is 47 GB.
void checkPictureMemory(const RunContext& context, const Bounds& b, double pitch) {
    const double width = std::ceil((b.hi.x - b.lo.x) / pitch) + 5;
    const double height = std::ceil((b.hi.y - b.lo.y) / pitch) + 5;
    const std::string what = "layer pictures of " + formatCount(width) + " x " +
                             formatCount(height) + " pixels at --pitch " +
                             formatQuantity(pitch * 1000.0) + " um";
    checkMemory(context, width * height * PICTURE_BYTES_PER_PIXEL, what, "use a coarser --pitch");
    // A picture beyond 16384^2 pixels is more than any viewer shows and takes minutes per layer.
    if (width * height > MAX_PICTURE_PIXELS)
        throw ResourceError(what +
                            " exceed the 16384 x 16384 pixels of a picture: use a coarser "
                            "--pitch");
}

/// Refuses, by bytes and before slicing, a layer stack too large for memory: its contours (one
/// vertex per crossing triangle, 16 B, x3 while slicing and linking), the slicer's buckets and
/// each layer's PolygonSet and JSON summary (~1 KiB).
void checkStackMemory(const RunContext& context, const Mesh& mesh, const SliceOptions& options,
                      int count, int sliced) {
    const double z0 = options.zStart.value_or(mesh.bounds().lo.z);
    const double vertices = pipeline::contourVertexCount(mesh, count, options.layerThickness, z0,
                                                         options.planePosition);
    const double perLayer = sliced < count ? vertices * sliced / std::max(count, 1) : vertices;
    checkMemory(context, perLayer * 48.0 + vertices * 4.0 + double(sliced) * 1024.0,
                "slicing into " + formatCount(double(sliced)) + " layers of " +
                    formatQuantity(options.layerThickness * 1000.0) + " um (" +
                    formatCount(vertices) + " contour vertices)",
                "use a thicker --layer or fewer --layers");
    // Measured: 5.5 million layers of a 28-triangle part took 105 s and 5 GB; a million layers
    // is 10 m of 10 um layers, more than any printer builds.
    if (sliced > 1000000)
        throw ResourceError("slicing into " + formatCount(double(sliced)) + " layers of " +
                            formatQuantity(options.layerThickness * 1000.0) +
                            " um would take minutes (more than a million layers): use a "
                            "thicker --layer or fewer --layers");
}

void runSlice(const SliceCliOptions& o, const RunContext& context) {
    const Mesh mesh = readStl(o.file, o.scale);
    SliceOptions options;
    options.layerThickness = parseQuantity(o.layer, dim::LENGTH, "--layer");
    if (options.layerThickness > 1.0) {
        logWarn("layer thickness " + formatQuantity(options.layerThickness) +
                " mm is unusually thick (a bare number is in mm; write e.g. 25um)");
    }
    options.planePosition = o.plane;
    if (!o.zStart.empty()) options.zStart = parseQuantity(o.zStart, dim::LENGTH, "--z-start");
    const Bounds bounds = mesh.bounds();
    double pitch = 0.0;
    if (!o.outDir.empty()) {  // pictures refused by size before any slicing
        pitch = parseQuantity(o.pitch, dim::LENGTH, "--pitch");
        if (!(pitch > 0.0)) throw InputError("must be positive", "", "--pitch");
        checkPictureMemory(context, bounds, pitch);
    }
    if (options.layerThickness > bounds.hi.z - bounds.lo.z)
        throw InputError("layer thickness " + formatQuantity(options.layerThickness) +
                             " mm is more than the part's height " +
                             formatQuantity(bounds.hi.z - bounds.lo.z) + " mm",
                         "", "--layer");
    const int count = layerCount(mesh, options);
    checkStackMemory(context, mesh, options, count,
                     o.layers.empty() ? count : int(o.layers.size()));
    const LayerStack stack = sliceToStack(mesh, options, o.file, o.layers);
    const std::vector<Layer>& layers = stack.layers;
    if (!o.save.empty()) stack.save(o.save);

    nlohmann::json out{{"file", o.file},
                       {"layer_thickness_mm", options.layerThickness},
                       {"plane_position", options.planePosition},
                       {"layer_count", count}};
    out["layers"] = nlohmann::json::array();
    for (const Layer& layer : layers) out["layers"].push_back(layerJson(layer));

    if (!o.outDir.empty()) {
        const Bounds b = mesh.bounds();
        const RasterGrid grid = RasterGrid::covering({b.lo.x, b.lo.y}, {b.hi.x, b.hi.y}, pitch, 2);
        std::vector<Layer> chosen;
        for (int k : pictureLayers(o.layers, count)) {
            auto it = std::find_if(layers.begin(), layers.end(),
                                   [k](const Layer& l) { return l.index == k; });
            if (it != layers.end()) chosen.push_back(*it);
        }
        writePictures(chosen, grid, o.outDir);
        writeFileAtomic(o.outDir + "/slices.json", out.dump(2) + "\n");
    }
    if (o.json) {
        cli::printJson(out);
        return;
    }
    std::printf("%s: %d layers of %g um (plane at %g of each layer)\n", o.file.c_str(), count,
                options.layerThickness * 1000.0, options.planePosition);
    const bool all = o.layers.empty() && layers.size() > 20;
    std::printf("  %6s %10s %12s %8s %6s\n", "layer", "z (mm)", "area (mm^2)", "outers", "holes");
    for (size_t i = 0; i < layers.size(); ++i) {
        if (all && i % (layers.size() / 10) != 0 && i + 1 != layers.size()) continue;  // a sample
        const Layer& l = layers[i];
        std::printf("  %6d %10.4f %12.6g %8zu %6zu\n", l.index, l.z, l.region.area(),
                    l.region.outerCount(), l.region.holeCount());
    }
}

vpsim::cli::CommandRegistration registerSlice{
    "slice", [](CLI::App& app, const vpsim::cli::Globals& g) {
        auto* cmd = app.add_subcommand("slice",
                                       "slice an STL part into layers (areas, contours, pictures)");
        auto o = std::make_shared<SliceCliOptions>();
        cmd->add_option("file", o->file, "STL file (binary or ASCII; mm)")->required();
        cmd->add_option("--layer", o->layer, "layer thickness, e.g. 25um (default 50um)");
        cmd->add_option("--plane", o->plane,
                        "where the slicing plane lies in each layer, 0 = bottom, 0.5 = middle "
                        "(default), 1 = top");
        cmd->add_option("--z-start", o->zStart,
                        "z of the bottom of layer 0 (default: the part's lowest z)");
        cmd->add_option("--scale", o->scale, "multiply STL coordinates (25.4 for inches)");
        cmd->add_option("--layers", o->layers, "only these layer indices, e.g. 0,10,20")
            ->delimiter(',');
        cmd->add_option("--out", o->outDir,
                        "write pictures of the chosen layers (--layers, else 5 spread) here");
        cmd->add_option("--save", o->save,
                        "save the layers' polygons as a layer stack JSON (geometry/layer_stack.h)");
        cmd->add_option("--pitch", o->pitch, "pixel pitch of the raster pictures (default 10um)");
        cmd->add_flag("--json", o->json,
                      "print {\"layers\": [{\"z\" (mm), \"area\" (mm^2), \"outer_contours\", "
                      "\"holes\"}, ...]}");
        cmd->callback([o, &g] { runSlice(*o, g.hostContext()); });
    }};

}  // namespace
