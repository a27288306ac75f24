// vpsim.mie, vpsim.material and vpsim.mc: Lorenz-Mie of one sphere, a material's optics with its
// phase-function table as arrays, and the photon Monte Carlo with `vpsim mc --json`'s figures.
#include <cmath>
#include <cstdio>

#include "bind_common.h"
#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/gpu/context.h"
#include "vpsim/optics/material_file.h"
#include "vpsim/optics/mie.h"
#include "vpsim/optics/mie_summary.h"
#include "vpsim/transport/mc_arguments.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim::python {
namespace {

optics::Complex refractiveIndex(const py::handle& m) {
    if (py::isinstance<py::str>(m)) return optics::parseRefractiveIndex(m.cast<std::string>(), "m");
    try {
        return m.cast<std::complex<double>>();
    } catch (const py::cast_error&) {
        throw InputError("expected a complex number, a number or a string such as '1.5-0.1i'", "",
                         "m");
    }
}

py::dict mie(const py::handle& m, double x, const std::vector<double>& angles) {
    const optics::Complex index = refractiveIndex(m);
    return fromJson(optics::mieSphereJson(index, x, angles));
}

py::dict material(const std::string& path, const std::vector<std::string>& overrides,
                  const std::vector<double>& angles, const std::vector<double>& cdfAngles) {
    const optics::MaterialDefinition definition = optics::loadMaterialDefinition(path, overrides);
    py::dict out;
    if (definition.isSlurry) {
        const optics::SlurryOptics s = optics::computeSlurryOptics(definition);
        out = fromJson(optics::slurryOpticsJson(s, angles, cdfAngles));
        out["slurry"] = true;
        out["g_medium"] = s.medium.g;
        out["refractive_index"] = s.medium.refractiveIndex;
        out["wavelength_mm"] = s.medium.wavelength;
        std::vector<double> edges = s.phase.thetaEdges, cdf = s.phase.cdf;
        std::vector<float> inverse = s.phase.inverseCdf;
        const py::ssize_t panels = py::ssize_t(edges.size());
        out["phase_theta_edges_rad"] = ownedArray(std::move(edges), {panels});
        out["phase_cdf"] = ownedArray(std::move(cdf), {py::ssize_t(s.phase.cdf.size())});
        out["phase_inverse_cdf"] =
            ownedArray(std::move(inverse), {py::ssize_t(s.phase.inverseCdf.size())});
    } else {
        const optics::MediumOptics& o = definition.optics;
        out["slurry"] = false;
        out["mua_per_mm"] = o.mua;
        out["mus_per_mm"] = o.mus;
        out["g"] = o.g;
        out["refractive_index"] = o.refractiveIndex;
        out["wavelength_mm"] = o.wavelength;
        out["scattering_mean_free_path_um"] = o.mus > 0 ? 1000.0 / o.mus : INFINITY;
        out["transport_mean_free_path_um"] = o.mus > 0 ? 1000.0 / (o.mus * (1.0 - o.g)) : INFINITY;
    }
    out["material"] = path;
    out["name"] = definition.name;
    return out;
}

/// `vpsim mc`'s set-up (transport::mcSetup) from keyword arguments named as its options.
transport::McSetup mcSetup(const std::string& path, const py::dict& a) {
    transport::McArguments m;
    m.photons = argumentText(a["photons"], "photons");
    m.seed = a["seed"].cast<uint32_t>();
    m.estimator = a["estimator"].cast<std::string>();
    m.roulette = a["roulette"].cast<double>();
    if (!a["thickness"].is_none()) m.thickness = argumentText(a["thickness"], "thickness");
    m.nOutside = a["n_outside"].cast<double>();
    m.beam = a["beam"].cast<std::string>();
    m.w0 = argumentText(a["w0"], "w0");
    m.directBeam = a["direct_beam"].cast<bool>();
    m.controlVariates = a["control_variates"].cast<bool>();
    for (auto d : a["depths"]) m.depths.push_back(argumentText(d, "depths"));
    m.rMax = argumentText(a["r_max"], "r_max");
    m.zMax = argumentText(a["z_max"], "z_max");
    m.bins = a["bins"].cast<uint32_t>();
    const auto overrides = a["overrides"].cast<std::vector<std::string>>();
    return transport::mcSetup(
        m, optics::loadMediumOptics(path, overrides), [](const std::string& key) { return key; },
        RunContext{});
}

py::dict mc(const std::string& path, const py::dict& arguments, const py::dict& settings,
            const py::object& progress) {
    const transport::McSetup setup = mcSetup(path, arguments);
    const RunContext context = runContext(settingsFrom(settings));
    transport::McResult r = withoutGil(
        progress, [&] { return transport::runPhotonMc(setup, gpu::monteCarloContext(context)); });
    nlohmann::json summary = r.summaryJson();
    summary["material"] = path;
    summary["seed"] = setup.seed;
    summary["thickness_mm"] =
        setup.thickness > 0 ? nlohmann::json(setup.thickness) : nlohmann::json("semi-infinite");
    py::dict out = fromJson(summary);
    // The (r, z) tally as absorbed fractions of the launched weight per bin, array[ir, iz].
    const double launched = double(r.launched());
    const uint32_t nr = setup.bins.rBins, nz = setup.bins.zBins;
    std::vector<double> bins(r.absorbedRZ.size());
    for (size_t i = 0; i < bins.size(); ++i) bins[i] = double(r.absorbedRZ[i]) / launched;
    if (bins.size() == size_t(nr) * nz)
        out["absorbed_rz"] =
            ownedArray(std::move(bins), {py::ssize_t(nr), py::ssize_t(nz)}, {1, py::ssize_t(nr)});
    return out;
}

}  // namespace

void bindOptics(py::module_& m) {
    m.def("_mie", &mie, py::arg("m"), py::arg("x"), py::arg("angles"));
    m.def("_material", &material, py::arg("path"), py::arg("overrides"), py::arg("angles"),
          py::arg("cdf_angles"));
    m.def("_mc", &mc, py::arg("path"), py::arg("arguments"), py::arg("settings"),
          py::arg("progress"));
}

}  // namespace vpsim::python
