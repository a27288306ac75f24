#include "vpsim/cure/print_through.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim::cure {
namespace {

void checkStack(const std::vector<double>& layerDoses, double layerThickness,
                double penetrationDepth) {
    if (!(layerThickness > 0.0) || !std::isfinite(layerThickness))
        throw InputError("layer thickness must be positive, got " + formatQuantity(layerThickness));
    if (!(penetrationDepth > 0.0) || !std::isfinite(penetrationDepth))
        throw InputError("penetration depth must be positive, got " +
                         formatQuantity(penetrationDepth));
    for (size_t i = 0; i < layerDoses.size(); ++i)
        if (!(layerDoses[i] >= 0.0) || !std::isfinite(layerDoses[i])) {
            std::ostringstream reason;
            reason << "layer " << i << " dose must be finite and non-negative, got "
                   << layerDoses[i];
            throw InputError(reason.str());
        }
}

}  // namespace

double printThroughDose(double surfaceDose, double distance, double penetrationDepth) {
    return surfaceDose * std::exp(-distance / penetrationDepth);
}

std::vector<double> accumulatedLayerDoses(const std::vector<double>& layerDoses,
                                          double layerThickness, double penetrationDepth) {
    checkStack(layerDoses, layerThickness, penetrationDepth);
    const double transmission = std::exp(-layerThickness / penetrationDepth);  // through one layer
    std::vector<double> accumulated(layerDoses.size());
    double fromAbove = 0.0;  // dose at the top of layer i from layers i+1..n-1
    for (size_t i = layerDoses.size(); i-- > 0;) {
        accumulated[i] = layerDoses[i] + fromAbove;
        fromAbove = transmission * accumulated[i];
    }
    return accumulated;
}

double accumulatedDoseAtHeight(const std::vector<double>& layerDoses, double layerThickness,
                               double penetrationDepth, double height) {
    checkStack(layerDoses, layerThickness, penetrationDepth);
    double sum = 0.0;
    for (size_t j = 0; j < layerDoses.size(); ++j) {
        double distance =
            double(j + 1) * layerThickness - height;  // from layer j's surface down to h
        if (distance >= -1e-12 * layerThickness)
            sum += printThroughDose(layerDoses[j], std::max(distance, 0.0), penetrationDepth);
    }
    return sum;
}

std::vector<double> accumulatedBottomDoses(const std::vector<double>& layerDoses,
                                           double layerThickness, double penetrationDepth) {
    std::vector<double> bottom =
        accumulatedLayerDoses(layerDoses, layerThickness, penetrationDepth);
    const double transmission = std::exp(-layerThickness / penetrationDepth);
    for (double& dose : bottom) dose *= transmission;
    return bottom;
}

}  // namespace vpsim::cure
