#include "vpsim/optimise/dlp/cured_profile.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/cure/print_through.h"

namespace vpsim::optimise {

std::vector<std::pair<double, double>> curedIntervals(const std::vector<double>& dose,
                                                      double layerThickness,
                                                      double penetrationDepth,
                                                      double criticalDose) {
    if (!(criticalDose > 0.0)) throw InputError("cured profile: critical dose must be positive");
    const std::vector<double> top =
        cure::accumulatedLayerDoses(dose, layerThickness, penetrationDepth);
    std::vector<std::pair<double, double>> out;
    for (size_t i = 0; i < top.size(); ++i) {
        if (top[i] < criticalDose) continue;
        const double z1 = double(i + 1) * layerThickness;
        const double z0 = std::max(double(i) * layerThickness,
                                   z1 - penetrationDepth * std::log(top[i] / criticalDose));
        if (!out.empty() && out.back().second >= z0 - 1e-12)
            out.back().second = z1;
        else
            out.emplace_back(z0, z1);
    }
    return out;
}

double curedLength(const std::vector<std::pair<double, double>>& intervals, double zMin,
                   double zMax) {
    double sum = 0.0;
    for (const auto& [a, b] : intervals)
        sum += std::max(0.0, std::min(b, zMax) - std::max(a, zMin));
    return sum;
}

double uncuredLength(const std::vector<std::pair<double, double>>& intervals, double zMin,
                     double zMax) {
    return (zMax - zMin) - curedLength(intervals, zMin, zMax);
}

}  // namespace vpsim::optimise
