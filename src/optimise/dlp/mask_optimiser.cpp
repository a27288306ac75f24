#include "vpsim/optimise/dlp/mask_optimiser.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/core/units.h"

namespace vpsim::optimise {

DlpMaskPlan planOptimisedMasks(const DlpLayerStack& part, const DlpProcess& process,
                               const DlpMaskPlannerSettings& settings,
                               const plan::GreyLevels& levels) {
    if (settings.maxDose > levels.maxDose() * (1.0 + 1e-9))
        throw InputError("optimised-mask: max_dose " + formatQuantity(settings.maxDose * 100.0) +
                         " mJ/cm^2 is above the brightest grey level's dose " +
                         formatQuantity(levels.maxDose() * 100.0) + " mJ/cm^2");
    DlpPartOptions o;
    o.problem.layerThickness = process.layerThickness;
    o.problem.rateConstant = process.rateConstant;
    o.problem.attenuation = 1.0 / process.penetrationDepth;
    o.problem.gelPoint = process.gelPoint;
    o.problem.maxDose = settings.maxDose;
    o.problem.targetConversion = settings.targetConversion;
    o.problem.penalty = settings.penalty;
    o.problem.bonding = settings.bonding;
    o.objective = settings.objective;
    o.geometric.margin = settings.margin;
    DlpMaskPlan out;
    out.optimised = optimiseDlpPart(part, o);
    nlohmann::json xyJson = nullptr;
    std::vector<std::vector<float>> columnDoses;
    if (settings.xyCoupling) {
        DlpXyOptions xy;
        xy.pixelPitch = process.pixelPitch;
        xy.blurRadius = process.blurRadius;
        xy.margin = settings.margin;
        DlpXyResult joint = optimiseDlpPartXy(part, o, xy, &out.optimised);
        xyJson = {{"seconds", joint.seconds},
                  {"start", joint.start},
                  {"iterations", joint.iterations},
                  {"objective_columns", joint.objectiveColumns},
                  {"objective_start", joint.objectiveStart},
                  {"objective_xy", joint.objectiveXy},
                  {"contour_error_columns_mm", joint.contourErrorColumns},
                  {"contour_error_xy_mm", joint.contourErrorXy}};
        columnDoses = std::move(out.optimised.dose);
        out.optimised = std::move(joint.doses);
    }
    std::vector<size_t> histogram(256, 0);
    out.plan.machine.layerThickness = process.layerThickness;
    out.plan.machine.pixelPitch = process.pixelPitch;
    double quantisationError = 0.0;
    size_t exposedPixels = 0;
    for (size_t k = 0; k < part.layers.size(); ++k) {
        plan::LayerPlan layer;
        layer.z = double(k + 1) * process.layerThickness;
        plan::MaskImage mask;
        mask.width = part.width, mask.height = part.height;
        mask.originX = process.originX, mask.originY = process.originY;
        mask.pixelPitch = process.pixelPitch;
        mask.dose.resize(out.optimised.dose[k].size());
        std::vector<uint8_t> grey(mask.dose.size());
        for (size_t p = 0; p < grey.size(); ++p) {
            const double d = out.optimised.dose[k][p];
            grey[p] = levels.quantise(d);
            mask.dose[p] = float(levels.dose(grey[p]));  // what the printer delivers
            if (d > 0.0) {
                ++histogram[grey[p]];
                ++exposedPixels;
                quantisationError = std::max(quantisationError, std::abs(mask.dose[p] - d));
            }
        }
        layer.masks.push_back(std::move(mask));
        out.plan.layers.push_back(std::move(layer));
        out.grey.push_back(std::move(grey));
    }
    if (!columnDoses.empty()) {  // the column optimum as the printer would get it
        out.columnPlan = out.plan;
        for (size_t k = 0; k < columnDoses.size(); ++k)
            for (size_t p = 0; p < columnDoses[k].size(); ++p)
                out.columnPlan.layers[k].masks[0].dose[p] =
                    float(levels.dose(levels.quantise(columnDoses[k][p])));
    }
    out.summary = {{"planner", "optimised-mask"},
                   {"objective",
                    settings.objective == DlpObjective::Geometric ? "geometric" : "conversion-l2"},
                   {"bonding", settings.bonding == Bonding::OwnLayer ? "own-layer" : "run-bottom"},
                   {"distinct_columns", out.optimised.distinctColumns},
                   {"max_optimality_gap", out.optimised.maxGap},
                   {"columns_with_gap", out.optimised.openColumns},
                   {"optimiser_seconds", out.optimised.seconds},
                   {"exposed_pixels", exposedPixels},
                   {"max_quantisation_error_mJ_per_cm2", quantisationError * 100.0},
                   {"grey_histogram", histogram},
                   {"xy_coupling", xyJson}};
    out.figures = dlpReportFigureData(out, part, process, settings, levels);
    const double uniform = settings.uniformDose >= 0.0
                               ? settings.uniformDose
                               : out.figures["mean_exposed_dose"].get<double>();
    if (uniform > 0.0) out.summary["uniform_comparison"] = {{"dose_mJ_per_cm2", uniform * 100.0}};
    return out;
}

void busiestColumn(const DlpLayerStack& part, int& bestX, int& bestY) {
    long best = -1;
    double bestDistance = 0.0;
    for (int y = 0; y < part.height; ++y)
        for (int x = 0; x < part.width; ++x) {
            const std::vector<uint8_t> c = columnProfile(part, x, y);
            long changes = 0;
            for (size_t k = 1; k < c.size(); ++k) changes += c[k] != c[k - 1];
            if (c.empty() || !std::count(c.begin(), c.end(), 1)) continue;
            const double dx = x - 0.5 * (part.width - 1), dy = y - 0.5 * (part.height - 1);
            const double distance = dx * dx + dy * dy;
            if (changes > best || (changes == best && distance < bestDistance))
                best = changes, bestDistance = distance, bestX = x, bestY = y;
        }
    if (best < 0) throw InputError("optimised-mask: the part has no solid pixel");
}

long busiestGreyLayer(const std::vector<std::vector<uint8_t>>& grey) {
    long best = 0;
    size_t bestCount = 0;
    for (size_t k = 0; k < grey.size(); ++k) {
        std::vector<uint8_t> seen(256, 0);
        for (uint8_t g : grey[k]) seen[g] = 1;
        seen[0] = 0;  // unexposed pixels
        const size_t count = size_t(std::count(seen.begin(), seen.end(), 1));
        if (count > bestCount) bestCount = count, best = long(k);
    }
    return best;
}

nlohmann::json dlpReportFigureData(const DlpMaskPlan& plan, const DlpLayerStack& part,
                                   const DlpProcess& process,
                                   const DlpMaskPlannerSettings& settings,
                                   const plan::GreyLevels& levels) {
    int x = 0, y = 0;
    if (settings.figureColumnGiven) {
        x = int(std::floor((settings.figureX - process.originX) / process.pixelPitch));
        y = int(std::floor((settings.figureY - process.originY) / process.pixelPitch));
        if (x < 0 || y < 0 || x >= part.width || y >= part.height)
            throw InputError("optimised-mask: figure_x, figure_y lie outside the masks", "",
                             "plan.figure_x");
    } else {
        busiestColumn(part, x, y);
    }
    long layer = settings.figureLayer >= 0 ? settings.figureLayer : busiestGreyLayer(plan.grey);
    if (layer >= long(part.layers.size()))
        throw InputError("optimised-mask: figure_layer " + std::to_string(layer) +
                             " is beyond the part's " + std::to_string(part.layers.size()) +
                             " layers",
                         "", "plan.figure_layer");
    double sum = 0.0, count = 0.0;
    for (const plan::LayerPlan& l : plan.plan.layers)
        for (const plan::MaskImage& m : l.masks)
            for (float d : m.dose)
                if (d > 0.0f) sum += d, count += 1.0;
    nlohmann::json greyDose = nlohmann::json::array();
    for (int g = 0; g < 256; ++g) greyDose.push_back(100.0 * levels.dose(uint8_t(g)));
    nlohmann::json column = dlpColumnFigureData(plan, part, process, x, y);
    column["x_mm"] = process.originX + (x + 0.5) * process.pixelPitch;
    column["y_mm"] = process.originY + (y + 0.5) * process.pixelPitch;
    column["gel_point"] = process.gelPoint;
    column["target_conversion"] = settings.targetConversion;
    return {{"column", column},
            {"layer", layer},
            {"grey_dose_mJ_per_cm2", greyDose},
            {"mean_exposed_dose", count > 0.0 ? sum / count : 0.0}};
}

nlohmann::json dlpColumnFigureData(const DlpMaskPlan& plan, const DlpLayerStack& part,
                                   const DlpProcess& process, int x, int y) {
    if (x < 0 || y < 0 || x >= part.width || y >= part.height)
        throw InputError("optimised-mask: figure column outside the masks");
    const size_t p = size_t(y) * size_t(part.width) + size_t(x);
    const size_t n = part.layers.size();
    std::vector<double> quantised(n);
    nlohmann::json z = nlohmann::json::array(), solid = z, dose = z, qdose = z, conversion = z;
    for (size_t k = 0; k < n; ++k) quantised[k] = plan.plan.layers[k].masks[0].dose[p];
    // Accumulated dose at each layer's top node (Eq. 4), then Phi = 1 - exp(-K D) (Eq. 1).
    const double r = std::exp(-process.layerThickness / process.penetrationDepth);
    std::vector<double> accumulated(n);
    double carried = 0.0;
    for (size_t k = n; k-- > 0;) accumulated[k] = carried = quantised[k] + r * carried;
    for (size_t k = 0; k < n; ++k) {
        z.push_back(double(k + 1) * process.layerThickness);
        solid.push_back(part.layers[k][p] != 0);
        dose.push_back(100.0 * plan.optimised.dose[k][p]);
        qdose.push_back(100.0 * quantised[k]);
        conversion.push_back(-std::expm1(-process.rateConstant * accumulated[k]));
    }
    return {{"z_mm", z},
            {"solid", solid},
            {"dose_mJ_per_cm2", dose},
            {"quantised_dose_mJ_per_cm2", qdose},
            {"conversion", conversion}};
}

}  // namespace vpsim::optimise
