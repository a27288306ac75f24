#include "vpsim/report/job_result.h"

namespace vpsim::report {

nlohmann::json toJson(const JobResult& r) {
    nlohmann::json report{
        {"job", r.jobFile}, {"name", r.name}, {"backend", r.backend}, {"cure", r.cure}};
    report["part"] = {{"volume_mm3", r.part.volume},
                      {"size_mm", {r.part.size[0], r.part.size[1], r.part.size[2]}},
                      {"triangles", r.part.triangles}};
    if (r.kernel) {
        const KernelSummary& k = *r.kernel;
        report["kernel"] = {{"We3D_um", k.beam.radius * 1e3},
                            {"De3D_um", k.beam.attenuationLength * 1e3},
                            {"zmax_um", k.beam.depthOfMaximum * 1e3},
                            {"fit_residual", k.fitResidual},
                            {"fit_energy_fraction", k.fitEnergyFraction},
                            {"estimator", k.estimator},
                            {"efficiency", k.beam.efficiency},
                            {"photons", k.photons},
                            {"from_cache", k.fromCache},
                            {"exposure_uses", k.tabulatedExposure ? "table" : "fit"}};
    }
    report.update(r.plan.planner);
    report["plan"] = {
        {"strategy", r.plan.strategy}, {"layers", r.plan.layers}, {"energy_mJ", r.plan.energy}};
    report["exports"] = r.exports;
    const ExposureSummary& e = r.exposure;
    report["exposure"] = {{"model", e.model},
                          {"backend", e.backend},
                          {"grid", {e.grid[0], e.grid[1], e.grid[2]}},
                          {"voxel_um", {e.voxel[0] * 1e3, e.voxel[1] * 1e3, e.voxel[2] * 1e3}},
                          {"engine_seconds", e.engineSeconds},
                          {"store_and_compare_seconds", e.sinkSeconds},
                          {"max_mJ_per_cm2", e.maxDose * 100.0},
                          {"stored_voxels", e.storedVoxels},
                          {"kept_energy_fraction", e.keptEnergyFraction},
                          {"beam",
                           {{"We3D_um", e.beam.radius * 1e3},
                            {"De3D_um", e.beam.attenuationLength * 1e3},
                            {"efficiency", e.beam.efficiency}}}};
    report["cured_volume_mm3"] = r.curedVolume;
    if (!r.mpi.is_null()) report["mpi"] = r.mpi;
    const ValidationReport& v = r.validation;
    report["iou"] = v.slices.iou;
    report["surface_deviation_mm"] = v.deviation.toJson();
    report["overcure_below_downfacing_mm"] = v.slices.overcureBelowDownFacingMedian;
    report["validation"] = v.slices.toJson();
    if (!v.features.probes.empty()) report["features"] = v.features.toJson();
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [stage, seconds] : r.stageSeconds) stages[stage] = seconds;
    report["stage_seconds"] = stages;
    report["inputs"] = r.inputs;
    nlohmann::json pictures{
        {"deviation_scale",
         {{"limit_um", r.deviationLimit * 1000}, {"beyond_fraction", r.beyondDeviationLimit}}}};
    if (r.viewer) {
        const ViewerSummary& view = *r.viewer;
        pictures["viewer3d"] = {
            {"cured_triangles", view.curedTriangles},     {"cured_shown", view.curedShown},
            {"model_triangles", view.modelTriangles},     {"model_shown", view.modelShown},
            {"cluster_cell_um", view.clusterCell * 1000}, {"data_bytes", view.dataBytes}};
        if (!view.missing.empty()) pictures["viewer3d"]["missing"] = view.missing;
    }
    if (r.sectionView) {
        const SectionViewSummary& view = *r.sectionView;
        pictures["sections"] = {{"layers", view.layers},
                                {"layers_kept", view.layersKept},
                                {"pixels", {view.width, view.height}},
                                {"pixel_um", view.pixelMm * 1000},
                                {"scale_max_mJ_cm2", view.scaleMax},
                                {"above_scale", view.aboveScale},
                                {"kernel", view.kernel},
                                {"data_bytes", view.dataBytes}};
    }
    report["report"] = pictures;
    return report;
}

}  // namespace vpsim::report
