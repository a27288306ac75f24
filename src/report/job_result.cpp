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
                            {"efficiency", k.beam.efficiency},
                            {"photons", k.photons},
                            {"from_cache", k.fromCache},
                            {"exposure_uses", k.tabulatedExposure ? "table" : "fit"}};
    }
    report.update(r.plan.planner);
    report["plan"] = {
        {"strategy", r.plan.strategy}, {"layers", r.plan.layers}, {"energy_mJ", r.plan.energy}};
    const ExposureSummary& e = r.exposure;
    report["exposure"] = {{"model", e.model},
                          {"backend", e.backend},
                          {"grid", {e.grid[0], e.grid[1], e.grid[2]}},
                          {"voxel_um", {e.voxel[0] * 1e3, e.voxel[1] * 1e3, e.voxel[2] * 1e3}},
                          {"engine_seconds", e.engineSeconds},
                          {"store_and_compare_seconds", e.sinkSeconds},
                          {"max_mJ_per_cm2", e.maxDose * 100.0},
                          {"stored_voxels", e.storedVoxels},
                          {"beam",
                           {{"We3D_um", e.beam.radius * 1e3},
                            {"De3D_um", e.beam.attenuationLength * 1e3},
                            {"efficiency", e.beam.efficiency}}}};
    report["cured_volume_mm3"] = r.curedVolume;
    const ValidationReport& v = r.validation;
    report["iou"] = v.slices.iou;
    report["surface_deviation_mm"] = v.deviation.toJson();
    report["overcure_below_downfacing_mm"] = v.slices.overcureBelowDownFacingMedian;
    report["validation"] = v.slices.toJson();
    if (!v.features.probes.empty()) report["features"] = v.features.toJson();
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [stage, seconds] : r.stageSeconds) stages[stage] = seconds;
    report["stage_seconds"] = stages;
    return report;
}

}  // namespace vpsim::report
