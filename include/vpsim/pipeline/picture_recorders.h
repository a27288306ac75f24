#pragma once
/// @file
/// The whole-part pictures' slice consumers that a run's outputs ask for, made the same way by
/// rank 0 and by the MPI ranks that expose tiles (pipeline/cluster_run.h), so that each tile's
/// share merges into rank 0's: the figures' x-z and x-y sections, the 3D view's layer sections,
/// and the cured surface's kept picture (figures or viewer).

#include <optional>
#include <vector>

#include "vpsim/exposure/exposure_model.h"
#include "vpsim/geometry/layer_stack.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/pipeline/checkpoint.h"
#include "vpsim/pipeline/job.h"
#include "vpsim/report/figures.h"
#include "vpsim/report/layer_sections.h"
#include "vpsim/validate/streaming_surface.h"

namespace vpsim::pipeline {

struct PictureRecorders {
    std::optional<report::SectionRecorder> sections;            ///< figures
    std::optional<report::LayerSectionRecorder> layerSections;  ///< viewer
    /// `part`, `layers` and the job's cure law must outlive the recorders.
    PictureRecorders(const Job& job, const geometry::Mesh& part, const geometry::LayerStack& layers,
                     const exposure::ExposureGrid& grid);
    /// Their slice sinks, appended to `sinks`.
    void addSinks(std::vector<exposure::SliceSink>& sinks);
    /// Every consumer whose state is a whole-part picture: these recorders, `cured` when it
    /// keeps a view (keepsCuredView) and `exposureError`'s top map with the figures.
    PictureConsumers consumers(const Job& job, validate::StreamingCuredSurface* cured,
                               optimise::ExposureErrorSink* exposureError);
};

/// Whether the report's top view and 3D viewer need a picture of the cured surface (figures or
/// viewer among the outputs).
bool keepsCuredView(const Job& job);
/// Keeps that picture in `cured` when the job needs it: clustered as it is made when the whole
/// surface would outgrow the view (report::viewCell).
void keepCuredView(const Job& job, const geometry::Mesh& part, double voxelHeight,
                   validate::StreamingCuredSurface& cured);

}  // namespace vpsim::pipeline
