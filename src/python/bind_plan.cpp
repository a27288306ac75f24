// vpsim.plan, vpsim.Plan, vpsim.load_plan and vpsim.export: a job's scan plan (points and vectors
// as arrays per layer, masks as float32 arrays) in plan.json's format, and machine files through
// the registered exporters.
#include "bind_plan.h"

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/exporters/export_file.h"
#include "vpsim/pipeline/estimate.h"

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

/// Replaces mask `index` of every layer by the stack's layer k, stack[k] as set_mask takes it;
/// uint8 grey levels g give g / 255 of `fullDose`.
void setMasks(PlanObject& p, const py::array& stack, const py::object& fullDose, int index) {
    const py::ssize_t layers = py::ssize_t(p.plan.layers.size());
    if (stack.ndim() != 3 || stack.shape(0) != layers)
        throw InputError("expected an array (layers = " + std::to_string(layers) + ", nx, ny)", "",
                         "masks");
    py::object doses = stack;
    if (stack.dtype().is(py::dtype::of<uint8_t>())) {
        if (fullDose.is_none())
            throw InputError("uint8 masks are grey levels: give full_dose, the dose of level 255",
                             "", "full_dose");
        const double full = quantity(fullDose, dim::DOSE, "full_dose");
        if (!(full > 0 && std::isfinite(full))) throw InputError("must be > 0", "", "full_dose");
        doses = stack.attr("astype")("float64") * py::float_(full / 255.0);
    } else if (!fullDose.is_none()) {
        throw InputError("full_dose is for uint8 grey levels; float masks are doses", "",
                         "full_dose");
    }
    for (py::ssize_t k = 0; k < layers; ++k)
        setMask(p, int(k), py::array_t<float, py::array::forcecast>::ensure(doses[py::int_(k)]),
                index);
}

PlanObject planJob(const py::handle& jobArg, const std::string& baseDir,
                   const std::vector<std::string>& overrides, const py::handle& part,
                   const py::dict& settings, const py::object& progress) {
    const pipeline::Job job = loadJob(jobArg, baseDir, overrides, part);
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

/// As `vpsim export`: the named exporter, else the one whose default file has the path's
/// extension; returns its summary.
py::dict exportPlan(const PlanObject& p, const std::string& path, const std::string& name,
                    const py::handle& optionsArg) {
    exporters::ExportRequest request;
    request.path = path;
    request.exporter = name;
    if (!optionsArg.is_none()) request.options = toJson(optionsArg, "options");
    request.hint = "exporter= and options=";
    const nlohmann::json summary = [&] {
        py::gil_scoped_release release;
        return exporters::exportToFile(builtins().exporters, p.plan, request);
    }();
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
        .def("set_masks", &setMasks, py::arg("masks"), py::arg("full_dose") = py::none(),
             py::arg("mask") = 0,
             "replaces every layer's DLP mask by a stack, masks[k, ix, iy] for layer k (bottom "
             "up): float doses in mJ/mm^2, or uint8 grey levels g giving g / 255 of full_dose")
        .def(
            "copy", [](const PlanObject& p) { return p; }, "an independent copy")
        .def("__repr__", [](const PlanObject& p) {
            return "<vpsim.Plan " + p.strategy + ": " + std::to_string(p.plan.layers.size()) +
                   " layers, " + formatQuantity(p.plan.totalEnergy()) + " mJ>";
        });
    m.def("_plan", &planJob, py::arg("job"), py::arg("base_dir"), py::arg("overrides"),
          py::arg("part"), py::arg("settings"), py::arg("progress"));
    m.def("_load_plan", &planFrom, py::arg("source"));
    m.def("_export", &exportPlan, py::arg("plan"), py::arg("path"), py::arg("exporter"),
          py::arg("options"));
}

}  // namespace vpsim::python
