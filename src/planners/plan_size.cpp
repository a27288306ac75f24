#include "vpsim/planners/plan_size.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/text.h"

namespace vpsim::planners {
namespace {

constexpr double VECTOR_BYTES = 48.0, MOVE_BYTES = 72.0;

double maskPixels(const PlanSizeInputs& in) {
    const glm::dvec3 size = in.partBounds.size();
    const double pitch = in.machine.pixelPitch;
    return (std::ceil(size.x / pitch) + 4) * (std::ceil(size.y / pitch) + 4);
}

}  // namespace

PlanSize laserPlanSize(const PlanSizeInputs& in, double borderLoops) {
    const glm::dvec3 size = in.partBounds.size();
    const double spacing = 0.8 * in.machine.beamRadius;
    const double hatch = 1.5 * std::ceil(std::max(size.x, size.y) / spacing) * in.layers;
    const double vectors = hatch + borderLoops * in.contourVertices;
    PlanSize p;
    p.elements = vectors * 3;  // each vector, its mark and its jump
    p.planBytes = vectors * (VECTOR_BYTES + 2 * MOVE_BYTES);
    p.workingBytes = vectors * VECTOR_BYTES;  // a layer's vectors copied while ordering
    p.jsonBytes = vectors * 1800.0;
    // plan.json: a vector's 6 numbers and its trajectory's mark and jump (9 each), about 18
    // bytes a number: 260-270 bytes a vector measured on the laser examples.
    p.fileBytes = vectors * 280.0;
    p.seconds = vectors * 2e-6;
    p.detail = formatNumber(vectors, 3) + " vectors (hatch at " + formatNumber(spacing * 1e3, 3) +
               " um, " + formatNumber(borderLoops, 3) + " border loops)";
    return p;
}

PlanSize maskPlanSize(const PlanSizeInputs& in) {
    const double pixels = maskPixels(in) * in.layers;
    PlanSize p;
    p.elements = p.maskPixels = pixels;
    p.planBytes = pixels * 4.0;
    p.workingBytes = pixels * 1.0;  // the rasterised regions
    p.jsonBytes = pixels * 16.0;
    p.fileBytes = pixels * 20.0;  // a float's double in 17 digits and a comma; "0.0," outside
    p.seconds = pixels * 2e-8;
    p.detail = formatNumber(pixels, 3) + " mask pixels at " +
               formatNumber(in.machine.pixelPitch * 1e3, 3) + " um in " +
               std::to_string(in.layers) + " layers";
    return p;
}

PlanSize laserOptimiserPlanSize(const PlanSizeInputs& in, double gridPitch, double dotPitch,
                                double iterations, bool dotsInPlan) {
    PlanSize p = laserPlanSize(in);
    const double margin = 2 * (1.5 * in.beamRadius + 2 * in.beamRadius);
    const glm::dvec3 size = in.partBounds.size();
    const double cells =
        std::ceil((size.x + margin) / gridPitch) * std::ceil((size.y + margin) / gridPitch);
    const double dots = (size.x * size.y) / (dotPitch * dotPitch) * in.layers;
    p.workingBytes = cells * 4.0 * (12.0 + in.layers) + dots * 32.0;
    if (dotsInPlan) p.planBytes += dots * (VECTOR_BYTES + 2 * MOVE_BYTES);
    // In plan.json the dots the planner keeps are merged into vectors along a hatch row: 60
    // bytes a dot bound it (1.8 MB for 4e4 dots of the estimate test's inverse job).
    if (dotsInPlan) p.fileBytes += dots * 60.0;
    p.elements += dots;
    p.seconds += cells * in.layers * iterations * 2e-8;
    p.detail += "; planning grid " + formatNumber(cells, 3) + " cells at " +
                formatNumber(gridPitch * 1e3, 3) + " um, " + formatNumber(dots, 3) + " dots";
    return p;
}

PlanSize shapePlanSize(const PlanSizeInputs& in, double gridPitch, double dotPitch,
                       const optimise::ShapeParameters& parameters) {
    PlanSize p = laserOptimiserPlanSize(in, gridPitch, dotPitch, 0, true);
    const double margin = 2 * (1.5 * in.beamRadius + 2 * in.beamRadius);
    const glm::dvec3 size = in.partBounds.size();
    const double cells =
        std::ceil((size.x + margin) / gridPitch) * std::ceil((size.y + margin) / gridPitch);
    const double voxels = cells * in.layers * parameters.slicesPerLayer;
    p.workingBytes += voxels * (4 * 4.0 + 9.0);
    p.seconds += voxels * (parameters.iterations + parameters.coarseIterations / 6.0) * 3e-8;
    p.detail += "; shape objective on " + formatNumber(voxels, 3) + " voxels";
    return p;
}

PlanSize Planner::estimateSize(const PlanSizeInputs& inputs) const {
    return process() == plan::Process::Laser ? laserPlanSize(inputs) : maskPlanSize(inputs);
}

}  // namespace vpsim::planners
