#include "vpsim/planners/laser_layers.h"

#include <algorithm>

#include "vpsim/geometry/slicer.h"

namespace vpsim::planners {

std::vector<geometry::PolygonSet> layerRegions(const PlannerInputs& in) {
    std::vector<geometry::PolygonSet> regions;
    for (const auto& layer : in.layers.layers) regions.push_back(layer.region);
    return regions;
}

std::vector<double> layerTops(const plan::ScanPlan& empty) {
    std::vector<double> tops;
    for (const auto& layer : empty.layers) tops.push_back(layer.z);
    return tops;
}

std::vector<geometry::PolygonSet> shapeSlices(const PlannerInputs& in, const plan::ScanPlan& plan,
                                              int n) {
    const double h = in.machine.layerThickness;
    std::vector<geometry::PolygonSet> slices;
    for (size_t k = 0; k < plan.layers.size(); ++k)
        for (int s = 0; s < n; ++s)
            slices.push_back(in.part
                                 ? geometry::sliceAt(*in.part, plan.layers[k].z - (s + 0.5) * h / n)
                                 : in.layers.layers[k].region);
    return slices;
}

nlohmann::json compensationJson(const std::vector<optimise::LayerCompensation>& layers) {
    double area = 0, worst = 0, curing = 0;
    nlohmann::json where = nlohmann::json::array();
    for (size_t k = 0; k < layers.size(); ++k) {
        area += layers[k].uncompensableArea;
        curing += layers[k].curingOutsideArea;
        worst = std::max(worst, layers[k].uncompensableMax);
        if (layers[k].uncompensableArea > 0)
            where.push_back({{"layer", k},
                             {"area_mm2", layers[k].uncompensableArea},
                             {"max_excess_over_Etar", layers[k].uncompensableMax}});
    }
    return {{"uncompensable_area_mm2", area},
            {"uncompensable_max_excess_over_Etar", worst},
            {"transmitted_cures_outside_area_mm2", curing},
            {"uncompensable_layers", where}};
}

KeyTable laserOptimiserKeyTable(const std::string& dotPitchDoc, const char* dotPitchDefault) {
    return {{
        quantityKey("dot_pitch", dim::LENGTH, dotPitchDefault, dotPitchDoc).in(1e-4, 1.0),
        quantityKey("grid_pitch", dim::LENGTH, "10 um",
                    "planning grid: exposure maps and evaluation points")
            .in(1e-4, 1.0),
        booleanKey("compensate", true, "subtract the exposure the layers above transmit"),
    }};
}

}  // namespace vpsim::planners
