#include "vpsim/planners/laser_exposure_review.h"

#include <algorithm>
#include <cmath>

#include "vpsim/exposure/deposit.h"
#include "vpsim/exposure/exposure_engine.h"
#include "vpsim/optimise/laser/exposure_error.h"
#include "vpsim/optimise/laser/exposure_error_sink.h"
#include "vpsim/optimise/laser/exposure_figures.h"
#include "vpsim/plan/aces/aces.h"
#include "vpsim/plan/feature_blocks.h"

namespace vpsim::planners {
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

/// Etar = Ec exp((lt - zmax)/De3D) of the fitted beam (ACES's target dose) and the band Reff.
std::pair<double, double> targetAndBand(const plan::Machine& machine, const kernel::FittedBeam& b,
                                        const cure::CureLaw& cure) {
    const double lt = machine.layerThickness;
    return {plan::acesTargetDose(cure.criticalDose(), lt, std::min(b.depthOfMaximum, 0.99 * lt),
                                 b.attenuationLength),
            plan::effectiveRadius(b.radius)};
}

std::vector<geometry::PolygonSet> layerRegions(const geometry::LayerStack& layers) {
    std::vector<geometry::PolygonSet> regions;
    for (const auto& layer : layers.layers) regions.push_back(layer.region);
    return regions;
}

}  // namespace

std::unique_ptr<optimise::ExposureErrorSink> laserExposureErrorSink(
    const geometry::LayerStack& layers, const plan::Machine& machine, const cure::CureLaw& cure,
    const exposure::ExposureModel& model, bool figures) {
    const auto* fitted = dynamic_cast<const exposure::ExposureEngine*>(&model);
    std::vector<geometry::PolygonSet> regions = layerRegions(layers);
    if (machine.process != plan::Process::Laser || !fitted ||
        std::all_of(regions.begin(), regions.end(), [](const auto& r) { return r.empty(); }))
        return nullptr;
    const kernel::FittedBeam& b = fitted->beam();
    const auto [etar, band] = targetAndBand(machine, b, cure);
    const double voxelHeight = model.layerThickness() / model.grid().slicesPerLayer;
    return std::make_unique<optimise::ExposureErrorSink>(
        model.grid(), std::move(regions), etar, band,
        std::exp(0.5 * voxelHeight / b.attenuationLength), figures);
}

PlanReview laserExposureReview(const PlanReviewInputs& in) {
    const plan::ScanPlan& plan = in.plan;
    if (in.machine.process != plan::Process::Laser || plan.layers.empty() ||
        plan.layers.size() != in.layers.layers.size())
        return {};
    const std::vector<geometry::PolygonSet> regions = layerRegions(in.layers);
    const auto top = std::find_if(regions.rbegin(), regions.rend(),
                                  [](const geometry::PolygonSet& r) { return !r.empty(); });
    if (top == regions.rend()) return {};
    const kernel::FittedBeam& b = in.beam;
    const auto [etar, band] = targetAndBand(in.machine, b, in.cure);
    optimise::ExposureError all;
    exposure::SurfaceGrid topMap;
    nlohmann::json error;
    if (in.exposureError) {  // the run's own slices (vpsim run)
        error = in.exposureError->result(&all);
        if (in.figures) topMap = in.exposureError->topMap();
    } else {  // the plan exposed again, layer by layer, with the fitted beam on the run's grid
        exposure::ExposureGrid grid = in.model.grid();
        grid.slicesPerLayer = 1;
        exposure::ExposureEngine engine(grid, b, in.machine.layerThickness);
        error = optimise::planExposureError(engine, plan, regions, etar, band, &all, &topMap);
    }
    error["pitch_um"] = in.voxel * 1e3;
    PlanReview review;
    review.report["layer_exposure_error"] = std::move(error);
    if (!in.figures) return review;  // simulation.outputs leaves the figures out
    // The seed-style single layer: the top one, which nothing above reaches, cropped to its
    // region plus Reff and two beam radii.
    const size_t k = size_t(regions.rend() - top) - 1;
    const exposure::SurfaceGrid map = cropped(topMap, regions[k], band + 2 * b.radius);
    const optimise::ExposureError single =
        optimise::layerExposureError(map, regions[k], etar, band);
    optimise::writeSortedErrorFigure(
        in.outDir + "/exposure_error_sorted",
        "Sorted exposure error over the part plus Reff (seed 000 Fig. 23)",
        {{in.strategy + ", every layer (own + transmitted)", all.sortedRelative},
         {in.strategy + ", top layer", single.sortedRelative}});
    const double ec = in.cure.criticalDose();
    optimise::writeExposureMapFigure(in.outDir + "/exposure_top_layer",
                                     "Surface exposure of the top layer (" + in.strategy + ")", map,
                                     &regions[k], etar, ec, 2 * b.radius);
    review.sections.push_back(
        {"Exposure error of the plan (seed 000 Fig. 23)",
         {},
         {{"exposure_top_layer",
           "surface exposure of the top layer (mJ/cm^2; red: the model's outline)"},
          {"exposure_error_sorted",
           "sorted |exposure error| / Etar over the part plus Reff, "
           "every layer (seed 000 Fig. 23)"}}});
    return review;
}

PlanReview Planner::review(const PlanReviewInputs& inputs) const {
    return process() == plan::Process::Laser ? laserExposureReview(inputs) : PlanReview{};
}

}  // namespace vpsim::planners
