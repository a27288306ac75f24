// vpsim.kernel: the beam kernel I(r, z) of a material (photon Monte Carlo, the CLI's cache) as a
// 2D array with its axes, and its Eq. 12 fit with `vpsim kernel --json`'s figures.
#include "bind_common.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/kernel/kernel_arguments.h"
#include "vpsim/kernel/kernel_summary.h"

namespace vpsim::python {
namespace {

/// The kernel's table and curves as arrays, array[ir, iz] (a view of the table's z-major
/// storage: no copy).
void addArrays(py::dict& out, kernel::BeamKernel k) {
    const py::ssize_t nr = k.rBins, nz = k.zBins;
    std::vector<double> r(k.rBins), z(k.zBins);
    for (uint32_t i = 0; i < k.rBins; ++i) r[i] = (i + 0.5) * k.rBin;
    for (uint32_t i = 0; i < k.zBins; ++i) z[i] = (i + 0.5) * k.zBin;
    out["intensity"] = ownedArray(std::move(k.intensity), {nr, nz}, {1, nr});
    out["r"] = ownedArray(std::move(r), {nr});
    out["z"] = ownedArray(std::move(z), {nz});
    out["depth_amplitude"] = ownedArray(std::move(k.depthAmplitude), {nz});
    out["depth_radius"] = ownedArray(std::move(k.depthRadius), {nz});
}

py::dict beamKernel(const std::string& path, const py::dict& a, const py::dict& settings,
                    const py::object& progress) {
    kernel::KernelArguments given;
    given.power = argumentText(a["power"], "power");
    given.w0 = argumentText(a["w0"], "w0");
    given.photons = argumentText(a["photons"], "photons");
    given.seed = a["seed"].cast<uint32_t>();
    if (!a["thickness"].is_none()) given.thickness = argumentText(a["thickness"], "thickness");
    given.nOutside = a["n_outside"].cast<double>();
    if (!a["r_max"].is_none()) given.rMax = argumentText(a["r_max"], "r_max");
    if (!a["z_max"].is_none()) given.zMax = argumentText(a["z_max"], "z_max");
    given.bins = a["bins"].cast<uint32_t>();
    given.estimator = a["estimator"].cast<std::string>();
    const kernel::KernelOptions o =
        kernel::kernelOptions(given, [](const std::string& key) { return key; });
    const kernel::KernelRequest request =
        kernel::kernelRequest(path, o, a["overrides"].cast<std::vector<std::string>>());
    const RunContext context = runContext(settingsFrom(settings));
    bool fromCache = false;
    transport::McResult mc;
    kernel::BeamKernel k = withoutGil(
        progress, [&] { return kernel::cachedKernel(request, context, fromCache, &mc); });
    nlohmann::json summary = kernel::kernelSummaryJson(k, request.setup, fromCache);
    if (!fromCache) summary["monte_carlo"] = mc.summaryJson();
    summary["fitted_beam"] = kernel::fittedBeamOf(k).toJson();
    if (!a["out"].is_none()) {  // the files `vpsim kernel --out` writes
        const std::string dir = a["out"].cast<std::string>();
        withoutGil(py::none(), [&] {
            createDirectories(dir);
            k.save(dir + "/kernel.json");
            kernel::writeKernelVdb(dir + "/kernel.vdb", k);
            kernel::writeKernelFigures(dir, k);
        });
        summary["kernel"] = dir + "/kernel.json";
    }
    py::dict out = fromJson(summary);
    out["power_mW"] = k.power;
    out["photons"] = k.photons;
    out["r_bin_mm"] = k.rBin;
    out["z_bin_mm"] = k.zBin;
    out["mua_per_mm"] = k.mua;
    addArrays(out, std::move(k));
    return out;
}

}  // namespace

void bindKernel(py::module_& m) {
    m.def("_kernel", &beamKernel, py::arg("path"), py::arg("arguments"), py::arg("settings"),
          py::arg("progress"));
}

}  // namespace vpsim::python
