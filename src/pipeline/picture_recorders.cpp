#include "vpsim/pipeline/picture_recorders.h"

#include "vpsim/report/viewer3d.h"

namespace vpsim::pipeline {

PictureRecorders::PictureRecorders(const Job& job, const geometry::Mesh& part,
                                   const geometry::LayerStack& layers,
                                   const exposure::ExposureGrid& grid) {
    const SimulationSpec& sim = job.simulation;
    const int count = int(layers.layers.size());
    if (sim.writes("figures")) {
        std::vector<geometry::PolygonSet> regions;
        for (const auto& layer : layers.layers) regions.push_back(layer.region);
        sections.emplace(part, grid, count * sim.slicesPerLayer, *job.cure, count / 2,
                         report::busiestRow(regions, grid));
    }
    if (sim.writes("viewer")) layerSections.emplace(layers, grid, *job.cure);
}

void PictureRecorders::addSinks(std::vector<exposure::SliceSink>& sinks) {
    auto sink = [](auto& consumer) {
        return [&consumer](const exposure::ExposureSlice& s) { consumer.add(s); };
    };
    if (sections) sinks.push_back(sink(*sections));
    if (layerSections) sinks.push_back(sink(*layerSections));
}

PictureConsumers PictureRecorders::consumers(const Job& job, validate::StreamingCuredSurface* cured,
                                             optimise::ExposureErrorSink* exposureError) {
    PictureConsumers pictures;
    if (keepsCuredView(job)) pictures.cured = cured;
    if (sections) pictures.sections = &*sections;
    if (layerSections) pictures.layerSections = &*layerSections;
    if (job.simulation.writes("figures")) pictures.exposureError = exposureError;
    return pictures;
}

bool keepsCuredView(const Job& job) {
    return job.simulation.writes("figures") || job.simulation.writes("viewer");
}

void keepCuredView(const Job& job, const geometry::Mesh& part, double voxelHeight,
                   validate::StreamingCuredSurface& cured) {
    if (keepsCuredView(job))
        cured.keepView(report::viewCell(part.area(), job.simulation.voxel, voxelHeight));
}

}  // namespace vpsim::pipeline
