// The planners' terms of a job's estimate (estimate.h), for the built-in strategies that do not
// override plan::Planner::estimateSize. Each reads the keys it needs from the plan section as
// written (defaults as the planners document them); the figures are orders of magnitude:
//  laser   hatch lines at 0.8 w0 (ACES's spacing for 1% homogeneity; the default job's plan at
//          1 m has 63 um at w0 = 50 um) across the part's larger side, 1.5 segments each, plus
//          `border_count` loops of each layer's contour vertices: LaserVector 48 B, and the
//          trajectories scanStage adds (a mark and a jump per vector, ScanMove 72 B). Writing
//          plan.json (a json array of 6 numbers per vector, 9 per move, then the dumped text)
//          and ordering: measured 2.1 kB per vector at the plan stage's peak (1 m default job).
//  masks   one float mask per layer over the part's box + 2 pixels (plan/dlp_masks.cpp).
//  optimised-mask  the voxelised part and the optimiser's doses, grey levels and conversions
//          (8 fields of 4 B per pixel per layer); xy_coupling adds dlp_xy.cpp's six 3D fields
//          on a grid of 2 x 2 cells per pixel (its peakFieldMiB).
//  dfbtp/inverse   the planning grid (grid_pitch, default 10 um) over the part's box grown by
//          the effective radius + 2 W: a dozen float maps per layer, the transmitted exposure
//          of every layer kept for top-down compensation, and the dots (dot_pitch) x 32 B.
#include <algorithm>
#include <cmath>

#include "vpsim/core/text.h"
#include "vpsim/core/units.h"
#include "vpsim/pipeline/estimate.h"

namespace vpsim::pipeline {
namespace {

constexpr double VECTOR_BYTES = 48.0, MOVE_BYTES = 72.0;

double lengthKey(const nlohmann::json& options, const char* key, double fallback) {
    if (!options.is_object() || !options.contains(key)) return fallback;
    return quantityFromJson(options.at(key), dim::LENGTH, std::string("plan.") + key);
}

double numberKey(const nlohmann::json& options, const char* key, double fallback) {
    if (!options.is_object() || !options.contains(key) || !options.at(key).is_number())
        return fallback;
    return options.at(key).get<double>();
}

plan::PlanSize laserPlan(const plan::PlanSizeInputs& in) {
    const glm::dvec3 size = in.partBounds.size();
    const double spacing = 0.8 * in.machine.beamRadius;
    const double borders = numberKey(in.options, "border_count", 1);
    const double hatch = 1.5 * std::ceil(std::max(size.x, size.y) / spacing) * in.layers;
    const double vectors = hatch + borders * in.contourVertices;
    plan::PlanSize p;
    p.elements = vectors * 3;  // each vector, its mark and its jump
    p.planBytes = vectors * (VECTOR_BYTES + 2 * MOVE_BYTES);
    p.workingBytes = vectors * VECTOR_BYTES;  // a layer's vectors copied while ordering
    p.jsonBytes = vectors * 1800.0;
    p.fileBytes = vectors * 130.0;
    p.seconds = vectors * 2e-6;
    p.detail = formatNumber(vectors, 3) + " vectors (hatch at " + formatNumber(spacing * 1e3, 3) +
               " um, " + formatNumber(borders, 3) + " border loops)";
    return p;
}

double maskPixels(const plan::PlanSizeInputs& in) {
    const glm::dvec3 size = in.partBounds.size();
    const double pitch = in.machine.pixelPitch;
    return (std::ceil(size.x / pitch) + 4) * (std::ceil(size.y / pitch) + 4);
}

plan::PlanSize maskPlan(const plan::PlanSizeInputs& in) {
    const double pixels = maskPixels(in) * in.layers;
    plan::PlanSize p;
    p.elements = p.maskPixels = pixels;
    p.planBytes = pixels * 4.0;
    p.workingBytes = pixels * 1.0;  // the rasterised regions
    p.jsonBytes = pixels * 16.0;
    p.fileBytes = pixels * 10.0;
    p.seconds = pixels * 2e-8;
    p.detail = formatNumber(pixels, 3) + " mask pixels at " +
               formatNumber(in.machine.pixelPitch * 1e3, 3) + " um in " +
               std::to_string(in.layers) + " layers";
    return p;
}

plan::PlanSize optimisedMaskPlan(const plan::PlanSizeInputs& in) {
    plan::PlanSize p = maskPlan(in);
    p.workingBytes = p.maskPixels * 8.0 * 4.0;
    p.seconds = p.maskPixels * 2e-6;
    const bool xy = in.options.is_object() && in.options.value("xy_coupling", false);
    if (xy) {
        p.workingBytes += p.maskPixels * 4.0 * 6.0 * 4.0;  // six fields, 2 x 2 cells per pixel
        p.seconds += p.maskPixels * 4.0 * 60 * 4e-8;       // 60 FISTA iterations
        p.detail += ", xy_coupling: six 3D fields at 2 x 2 cells per pixel";
    }
    return p;
}

plan::PlanSize laserOptimiserPlan(const plan::PlanSizeInputs& in, bool inverse) {
    plan::PlanSize p = laserPlan(in);
    const double grid = lengthKey(in.options, "grid_pitch", 0.01);
    const double dot = lengthKey(in.options, "dot_pitch", 0.02);
    const double margin = 2 * (1.5 * in.beamRadius + 2 * in.beamRadius);
    const glm::dvec3 size = in.partBounds.size();
    const double cells = std::ceil((size.x + margin) / grid) * std::ceil((size.y + margin) / grid);
    const double dots = (size.x * size.y) / (dot * dot) * in.layers;
    p.workingBytes = cells * 4.0 * (12.0 + in.layers) + dots * 32.0;
    if (inverse) p.planBytes += dots * (VECTOR_BYTES + 2 * MOVE_BYTES);
    p.elements += dots;
    const double iterations = inverse ? numberKey(in.options, "iterations", 40) : 4;
    p.seconds += cells * in.layers * iterations * 2e-8;
    p.detail += "; planning grid " + formatNumber(cells, 3) + " cells at " +
                formatNumber(grid * 1e3, 3) + " um, " + formatNumber(dots, 3) + " dots";
    return p;
}

}  // namespace

plan::PlanSize estimatePlan(const Job& job, const plan::PlanSizeInputs& inputs) {
    if (job.planner) {
        if (std::optional<plan::PlanSize> own = job.planner->estimateSize(inputs)) return *own;
    }
    if (job.strategy == "optimised-mask") return optimisedMaskPlan(inputs);
    if (job.strategy == "dfbtp") return laserOptimiserPlan(inputs, false);
    if (job.strategy == "inverse") return laserOptimiserPlan(inputs, true);
    return job.machine.process == plan::Process::Laser ? laserPlan(inputs) : maskPlan(inputs);
}

}  // namespace vpsim::pipeline
