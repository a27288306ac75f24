#include "vpsim/pipeline/laser_report.h"

#include <algorithm>
#include <cmath>

#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/dfbtp_exposure_error.h"
#include "vpsim/optimise/dfbtp_planner.h"
#include "vpsim/plan/aces.h"
#include "vpsim/plan/feature_blocks.h"
#include "vpsim/report/laser_figures.h"

namespace vpsim::pipeline {
namespace {

/// The cells of `map` within `margin` (mm) of `region`'s bounding box.
exposure::SurfaceGrid cropped(const exposure::SurfaceGrid& map, const geometry::PolygonSet& region,
                              double margin) {
    const auto [lo, hi] = region.bounds();
    const int i0 = std::max(0, int(std::floor((lo.x - margin - map.originX) / map.pitch)));
    const int j0 = std::max(0, int(std::floor((lo.y - margin - map.originY) / map.pitch)));
    const int i1 = std::min(map.nx, int(std::ceil((hi.x + margin - map.originX) / map.pitch)));
    const int j1 = std::min(map.ny, int(std::ceil((hi.y + margin - map.originY) / map.pitch)));
    if (i1 <= i0 || j1 <= j0) return map;
    exposure::SurfaceGrid out(i1 - i0, j1 - j0, map.originX + i0 * map.pitch,
                              map.originY + j0 * map.pitch, map.pitch);
    for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i)
            out.values[size_t(j - j0) * out.nx + (i - i0)] = map.values[size_t(j) * map.nx + i];
    return out;
}

}  // namespace

nlohmann::json laserErrorStage(const Job& job, const geometry::LayerStack& layers,
                               const plan::ScanPlan& plan, const BeamResult& beam,
                               const std::string& outDir) {
    if (job.machine.process != plan::Process::Laser || plan.layers.empty() ||
        plan.layers.size() != layers.layers.size())
        return nullptr;
    std::vector<geometry::PolygonSet> regions;
    for (const auto& layer : layers.layers) regions.push_back(layer.region);
    const auto top = std::find_if(regions.rbegin(), regions.rend(),
                                  [](const geometry::PolygonSet& r) { return !r.empty(); });
    if (top == regions.rend()) return nullptr;
    const kernel::FittedBeam& b = beam.beam;
    const double lt = job.machine.layerThickness, ec = job.cure->criticalDose();
    const double etar =
        plan::acesTargetDose(ec, lt, std::min(b.depthOfMaximum, 0.99 * lt), b.attenuationLength);
    exposure::ExposureEngine engine(optimise::planningGrid(regions, b.radius, job.simulation.voxel),
                                    b, lt);
    optimise::ExposureError all;
    nlohmann::json error = optimise::planExposureError(engine, plan, regions, etar,
                                                       plan::effectiveRadius(b.radius), &all);
    error["pitch_um"] = job.simulation.voxel * 1e3;
    // The seed-style single layer: the top one, which nothing above reaches, cropped to its
    // region plus Reff and two beam radii.
    const size_t k = size_t(regions.rend() - top) - 1;
    exposure::SurfaceGrid deposit = engine.grid().surface();
    exposure::depositLayer(plan.layers[k], deposit);
    const exposure::SurfaceGrid map = cropped(engine.layerMap(deposit, 0.0), regions[k],
                                              plan::effectiveRadius(b.radius) + 2 * b.radius);
    const optimise::ExposureError single =
        optimise::layerExposureError(map, regions[k], etar, plan::effectiveRadius(b.radius));
    report::writeSortedErrorFigure(
        outDir + "/exposure_error_sorted.svg",
        {{job.strategy + ", every layer (own + transmitted)", all.sortedRelative},
         {job.strategy + ", top layer", single.sortedRelative}});
    report::writeLayerExposureFigure(outDir + "/exposure_top_layer.svg", map, regions[k], etar, ec,
                                     "Surface exposure of the top layer (" + job.strategy + ")");
    return error;
}

}  // namespace vpsim::pipeline
