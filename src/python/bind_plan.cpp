// vpsim.plan, vpsim.Plan, vpsim.load_plan and vpsim.export: a job's scan plan (points and vectors
// as arrays per layer, masks as float32 arrays) in plan.json's format, and machine files through
// the registered exporters.
#include "bind_plan.h"

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/pipeline/estimate.h"
#include "vpsim/plan/machine/build_time.h"

namespace vpsim::python {

JobFront jobFront(const pipeline::Job& job, const RunContext& context, bool planOnly,
                  bool savedPlan) {
    JobFront f;
    f.part = pipeline::partStage(job);
    pipeline::checkEstimate(
        pipeline::estimateJob(job, f.part, planOnly, savedPlan, context.gpu != nullptr), context);
    f.bounds = f.part.bounds();
    f.beam = pipeline::beamStage(job, context);
    f.layers = pipeline::sliceStage(job, f.part);
    return f;
}

namespace {

py::dict layerDict(const plan::LayerPlan& layer) {
    py::dict out;
    out["z"] = layer.z;
    std::vector<double> points, vectors;
    for (const auto& p : layer.points) points.insert(points.end(), {p.x, p.y, p.energy});
    for (const auto& v : layer.vectors)
        vectors.insert(vectors.end(), {v.x0, v.y0, v.x1, v.y1, v.power, v.speed});
    out["points"] = ownedArray(std::move(points), {py::ssize_t(layer.points.size()), 3});
    out["vectors"] = ownedArray(std::move(vectors), {py::ssize_t(layer.vectors.size()), 6});
    py::list masks;
    for (const auto& mask : layer.masks) {
        py::dict d;
        std::vector<float> dose(mask.dose.size());  // array[ix, iy]
        for (int j = 0; j < mask.height; ++j)
            for (int i = 0; i < mask.width; ++i)
                dose[size_t(i) * mask.height + j] = mask.dose[size_t(j) * mask.width + i];
        d["dose"] = ownedArray(std::move(dose), {mask.width, mask.height});
        d["origin"] = py::make_tuple(mask.originX, mask.originY);
        d["pixel_pitch"] = mask.pixelPitch;
        masks.append(d);
    }
    out["masks"] = masks;
    return out;
}

/// Replaces layer `k`'s mask `index` by `dose` (mJ/mm^2, array[ix, iy] of the mask's shape).
void setMask(PlanObject& p, int k, const py::array_t<float, py::array::forcecast>& dose,
             int index) {
    if (k < 0 || k >= int(p.plan.layers.size()))
        throw InputError("layer " + std::to_string(k) + " is not in the plan", "", "layer");
    auto& masks = p.plan.layers[size_t(k)].masks;
    if (index < 0 || index >= int(masks.size()))
        throw InputError("layer " + std::to_string(k) + " has no mask " + std::to_string(index), "",
                         "mask");
    plan::MaskImage& mask = masks[size_t(index)];
    if (dose.ndim() != 2 || dose.shape(0) != mask.width || dose.shape(1) != mask.height)
        throw InputError("expected an array of shape (" + std::to_string(mask.width) + ", " +
                             std::to_string(mask.height) + ") (x, y)",
                         "", "dose");
    auto d = dose.unchecked<2>();
    for (int j = 0; j < mask.height; ++j)
        for (int i = 0; i < mask.width; ++i) {
            const float v = d(i, j);
            if (!(v >= 0 && std::isfinite(v)))
                throw InputError("doses must be finite and >= 0", "", "dose");
            mask.dose[size_t(j) * mask.width + i] = v;
        }
}

PlanObject planJob(const py::handle& jobArg, const std::string& baseDir,
                   const std::vector<std::string>& overrides, const py::dict& settings,
                   const py::object& progress) {
    const pipeline::Job job = loadJob(jobArg, baseDir, overrides);
    const RunContext context = runContext(settingsFrom(settings));
    return withoutGil(progress, [&] {
        JobFront f = jobFront(job, context, true, false);
        pipeline::PlanResult planned =
            pipeline::planStage(job, f.layers, f.bounds, f.beam, context);
        pipeline::scanStage(job, f.layers, planned.plan);  // trajectories, as plan.json has them
        return PlanObject{std::move(planned.plan), std::move(planned.summary), job.strategy};
    });
}

PlanObject planFrom(const py::handle& source) {
    if (py::isinstance<py::dict>(source))
        return PlanObject{plan::scanPlanFromJson(toJson(source, "<plan dict>"), "<plan dict>"),
                          nlohmann::json::object(), "saved plan"};
    const std::string path = toJson(source, "plan").get<std::string>();
    return PlanObject{plan::loadScanPlan(path), nlohmann::json::object(), "saved plan " + path};
}

std::string extensionOf(const std::string& path) {
    const size_t dot = path.find_last_of('.'), slash = path.find_last_of('/');
    return dot == std::string::npos || (slash != std::string::npos && dot < slash)
               ? std::string()
               : path.substr(dot);
}

/// As `vpsim export`: the named exporter, else the one whose default file has the path's
/// extension; returns its summary.
py::dict exportPlan(const PlanObject& p, const std::string& path, const std::string& name,
                    const py::handle& optionsArg) {
    const nlohmann::json options =
        optionsArg.is_none() ? nlohmann::json::object() : toJson(optionsArg, "options");
    const auto& registry = builtins().exporters;
    std::string chosen = name;
    if (chosen.empty()) {
        for (const auto& [entryName, entry] : registry.entries()) {
            try {
                auto exporter = registry.create(entryName, ConfigNode(options, "options"));
                if (extensionOf(exporter->defaultFileName()) == extensionOf(path)) {
                    chosen = entryName;
                    break;
                }
            } catch (const InputError&) {}
        }
        if (chosen.empty())
            throw InputError("no exporter writes '" + extensionOf(path) +
                                 "' files with these options (give exporter= and options=)",
                             path);
    }
    ConfigNode section(options, "options");
    auto exporter = registry.create(chosen, section);
    section.checkUnknownKeys();
    std::string reason;
    if (!exporter->accepts(p.plan, reason)) throw InputError(chosen + ": " + reason, path);
    {
        py::gil_scoped_release release;
        exporter->write(p.plan, path);
    }
    size_t vectors = 0;
    bool dlp = false;
    for (const auto& layer : p.plan.layers) {
        vectors += layer.vectors.size();
        dlp = dlp || !layer.masks.empty();
    }
    nlohmann::json summary = {{"file", path},
                              {"exporter", chosen},
                              {"options", options},
                              {"layers", p.plan.layers.size()},
                              {"vectors", vectors}};
    if (!dlp) summary["build_time_s"] = plan::estimateBuildTime(p.plan, {}).toJson();
    return fromJson(summary);
}

}  // namespace

void bindPlan(py::module_& m) {
    py::class_<PlanObject>(m, "Plan",
                           "A scan plan: laser points and vectors or DLP masks per layer")
        .def_property_readonly(
            "layers",
            [](const PlanObject& p) {
                py::list out;
                for (const auto& l : p.plan.layers) out.append(layerDict(l));
                return out;
            },
            "per layer (bottom up): z (mm, top surface), points (n, 3: x, y "
            "mm, energy mJ), vectors (n, 6: x0, y0, x1, y1 mm, power mW, "
            "speed mm/s), masks [{dose (mJ/mm^2, array[ix, iy]), origin, "
            "pixel_pitch}]")
        .def(
            "layer",
            [](const PlanObject& p, int k) {
                if (k < 0) k += int(p.plan.layers.size());
                if (k < 0 || k >= int(p.plan.layers.size()))
                    throw py::index_error("layer out of range");
                return layerDict(p.plan.layers[size_t(k)]);
            },
            py::arg("index"))
        .def("__len__", [](const PlanObject& p) { return p.plan.layers.size(); })
        .def_property_readonly(
            "energy", [](const PlanObject& p) { return p.plan.totalEnergy(); },
            "total energy delivered, mJ")
        .def_property_readonly("strategy", [](const PlanObject& p) { return p.strategy; })
        .def_property_readonly(
            "process",
            [](const PlanObject& p) { return plan::processName(p.plan.machine.process); })
        .def_property_readonly(
            "summary", [](const PlanObject& p) { return fromJson(p.summary); },
            "the planner's figures")
        .def(
            "to_json", [](const PlanObject& p) { return fromJson(plan::toJson(p.plan)); },
            "the plan as plan.json's document")
        .def(
            "save",
            [](const PlanObject& p, const std::string& path) { plan::saveScanPlan(p.plan, path); },
            py::arg("path"), "writes plan.json's format (atomic)")
        .def("set_mask", &setMask, py::arg("layer"), py::arg("dose"), py::arg("mask") = 0,
             "replaces a DLP mask's doses (mJ/mm^2, array[ix, iy] of the mask's shape)")
        .def("__repr__", [](const PlanObject& p) {
            return "<vpsim.Plan " + p.strategy + ": " + std::to_string(p.plan.layers.size()) +
                   " layers, " + formatQuantity(p.plan.totalEnergy()) + " mJ>";
        });
    m.def("_plan", &planJob, py::arg("job"), py::arg("base_dir"), py::arg("overrides"),
          py::arg("settings"), py::arg("progress"));
    m.def("_load_plan", &planFrom, py::arg("source"));
    m.def("_export", &exportPlan, py::arg("plan"), py::arg("path"), py::arg("exporter"),
          py::arg("options"));
}

}  // namespace vpsim::python
