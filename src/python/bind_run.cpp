// vpsim.run (the whole job: report.json's document), vpsim.components (every registered
// planner, cure law and exporter with its key table) and vpsim.calibrate (a working curve's fit).
#include "bind_common.h"
#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/cure/calibration.h"
#include "vpsim/pipeline/calibration_report.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/pipeline/run_job.h"

namespace vpsim::python {
namespace {

py::dict run(const py::handle& jobArg, const std::string& baseDir, const std::string& out,
             const std::vector<std::string>& overrides, const py::handle& part,
             const std::string& planFile, bool dryRun, const py::dict& settings,
             const py::object& progress) {
    const pipeline::Job job = loadJob(jobArg, baseDir, overrides, part);
    const Settings s = settingsFrom(settings);
    if (dryRun)  // the default memory budget: the library reads no environment
        return fromJson(pipeline::estimateJob(job, false, !planFile.empty(), s.backend != "cpu")
                            .toJson(RunContext{}));
    const RunContext context = runContext(s);
    pipeline::RunOptions options;
    options.planFile = planFile;
    const nlohmann::json report = withoutGil(
        progress, [&] { return report::toJson(pipeline::runJob(job, out, context, options)); });
    return fromJson(report);
}

py::dict calibrate(const py::array_t<double, py::array::forcecast>& doses,
                   const py::array_t<double, py::array::forcecast>& depths,
                   const py::object& gelPoint) {
    if (doses.ndim() != 1 || depths.ndim() != 1 || doses.size() != depths.size())
        throw InputError("expected two 1D arrays of the same length", "", "doses");
    std::optional<double> gel;
    if (!gelPoint.is_none()) {
        gel = gelPoint.cast<double>();
        if (!(*gel > 0.0 && *gel < 1.0))
            throw InputError("must lie strictly between 0 and 1", "", "gel_point");
    }
    cure::WorkingCurveData data;
    data.doseColumn = "dose_mJ_per_mm2";
    data.depthColumn = "depth_mm";
    for (py::ssize_t i = 0; i < doses.size(); ++i) {
        const double e = doses.at(i), d = depths.at(i);
        if (!(e > 0 && std::isfinite(e)) || !(d > 0 && std::isfinite(d)))
            throw InputError("point " + std::to_string(i) + ": doses and depths must be > 0", "",
                             "doses");
        data.dose.push_back(e);
        data.cureDepth.push_back(d);
        data.line.push_back(int(i) + 1);
    }
    const cure::WorkingCurveFit fit = cure::fitWorkingCurve(data.dose, data.cureDepth);
    return fromJson(pipeline::calibrationJson(builtins(), data, fit, gel));
}

}  // namespace

void bindRun(py::module_& m) {
    m.def("_run", &run, py::arg("job"), py::arg("base_dir"), py::arg("out"), py::arg("overrides"),
          py::arg("part"), py::arg("plan_file"), py::arg("dry_run"), py::arg("settings"),
          py::arg("progress"));
}

void bindComponents(py::module_& m) {
    m.def("_components", [] { return fromJson(pipeline::componentsJson(builtins())); });
    m.def("_calibrate", &calibrate, py::arg("doses"), py::arg("depths"), py::arg("gel_point"));
    m.def(
        "_set_log_level",
        [](const std::string& level) {  // as the CLI's VPSIM_LOG
            if (level == "error") return setLogLevel(LogLevel::Error);
            if (level == "warn") return setLogLevel(LogLevel::Warn);
            if (level == "info") return setLogLevel(LogLevel::Info);
            if (level == "debug") return setLogLevel(LogLevel::Debug);
            throw InputError("expected error, warn, info or debug, got " + level, "", "level");
        },
        py::arg("level"));
}

}  // namespace vpsim::python
