// BeamKernel: evaluation, JSON round trip, and the intensity estimate of seed 000 Eq. 11.

#include "vpsim/kernel/beam_kernel.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/transport/photon_mc.h"

namespace vpsim::kernel {

namespace {

constexpr double PI = 3.14159265358979323846;
constexpr double UM = 1000.0;  // micrometres per mm
constexpr const char* FORMAT = "vpsim-beam-kernel";

/// Position of x on bin centres 0.5, 1.5, ... (in bins): lower index and weight of the upper one.
void centreInterpolation(double x, uint32_t n, uint32_t& i0, uint32_t& i1, double& t) {
    double f = std::clamp(x - 0.5, 0.0, double(n - 1));
    i0 = std::min(uint32_t(f), n - 1);
    i1 = std::min(i0 + 1, n - 1);
    t = f - i0;
}

}  // namespace

double BeamKernel::sample(double r, double z) const {
    if (rBins == 0 || zBins == 0 || r < 0 || z < 0 || r > rBin * rBins || z > zBin * zBins)
        return 0.0;
    uint32_t r0, r1, z0, z1;
    double tr, tz;
    centreInterpolation(r / rBin, rBins, r0, r1, tr);
    centreInterpolation(z / zBin, zBins, z0, z1, tz);
    auto at = [this](uint32_t ir, uint32_t iz) {
        return double(intensity[size_t(iz) * rBins + ir]);
    };
    return (1 - tz) * ((1 - tr) * at(r0, z0) + tr * at(r1, z0)) +
           tz * ((1 - tr) * at(r0, z1) + tr * at(r1, z1));
}

double BeamKernel::fitted(double r, double z) const {
    if (fit.we3d <= 0 || fit.de3d <= 0) return 0.0;
    return fit.amplitude * std::exp(-2 * r * r / (fit.we3d * fit.we3d)) * std::exp(-z / fit.de3d);
}

double BeamKernel::beerLambert(double r, double z) const {
    double peak = (1 - specularReflectance) * 2 * power / (PI * w0 * w0);
    return peak * std::exp(-2 * r * r / (w0 * w0)) * std::exp(-mua * z);
}

nlohmann::json BeamKernel::toJson() const {
    nlohmann::json j;
    j["format"] = FORMAT;
    j["version"] = 1;
    j["power_mW"] = power;
    j["W0_um"] = w0 * UM;
    j["mua_per_mm"] = mua;
    j["specular_reflectance"] = specularReflectance;
    j["diffuse_reflectance"] = diffuseReflectance;
    j["photons"] = photons;
    j["We3D_um"] = fit.we3d * UM;
    j["De3D_um"] = fit.de3d * UM;
    j["zmax_um"] = zmax * UM;
    j["amplitude_mW_per_mm2"] = fit.amplitude;
    j["residual"] = fit.residual;
    j["fit_depth_start_um"] = fit.fitDepthStart * UM;
    // Both Eq. 12 fits and the energy each carries (fraction of the table's absorbed power).
    j["engine_fit"] = "least-squares";
    j["fit_energy_fraction"] = fit.energyFraction;
    j["energy_conserving_amplitude_mW_per_mm2"] = energyFit.amplitude;
    j["energy_conserving_residual"] = energyFit.residual;
    j["table_absorbed_fraction"] = tableAbsorbedFraction;
    j["r_bin_um"] = rBin * UM;
    j["z_bin_um"] = zBin * UM;
    j["r_bins"] = rBins;
    j["z_bins"] = zBins;
    j["depth_amplitude_mW_per_mm2"] = depthAmplitude;
    std::vector<double> radiusUm(depthRadius.size());
    for (size_t i = 0; i < depthRadius.size(); ++i) radiusUm[i] = depthRadius[i] * UM;
    j["depth_radius_um"] = radiusUm;
    nlohmann::json rows = nlohmann::json::array();
    for (uint32_t iz = 0; iz < zBins; ++iz)
        rows.push_back(std::vector<float>(intensity.begin() + size_t(iz) * rBins,
                                          intensity.begin() + size_t(iz + 1) * rBins));
    j["intensity_mW_per_mm2"] = rows;  // one row per depth slice
    return j;
}

BeamKernel BeamKernel::fromJson(const nlohmann::json& j, const std::string& file) {
    auto get = [&](const char* key) -> const nlohmann::json& {
        if (!j.is_object() || !j.contains(key))
            throw InputError("missing beam-kernel field", file, key);
        return j.at(key);
    };
    auto number = [&](const char* key) {
        const nlohmann::json& v = get(key);
        if (!v.is_number()) throw InputError("expected a number", file, key);
        return v.get<double>();
    };
    if (!get("format").is_string() || get("format").get<std::string>() != FORMAT)
        throw InputError(std::string("not a beam kernel (format must be '") + FORMAT + "')", file,
                         "format");
    BeamKernel k;
    k.power = number("power_mW");
    k.w0 = number("W0_um") / UM;
    k.mua = number("mua_per_mm");
    k.specularReflectance = number("specular_reflectance");
    k.diffuseReflectance = number("diffuse_reflectance");
    k.photons = uint64_t(number("photons"));
    k.fit.we3d = number("We3D_um") / UM;
    k.fit.de3d = number("De3D_um") / UM;
    k.zmax = number("zmax_um") / UM;
    k.fit.amplitude = number("amplitude_mW_per_mm2");
    k.fit.residual = number("residual");
    k.fit.fitDepthStart = number("fit_depth_start_um") / UM;
    k.rBin = number("r_bin_um") / UM;
    k.zBin = number("z_bin_um") / UM;
    double rBins = number("r_bins"), zBins = number("z_bins");
    if (!(k.rBin > 0 && k.zBin > 0 && rBins >= 1 && zBins >= 1 && rBins * zBins <= 1e8))
        throw InputError("bin sizes and counts must be positive", file, "r_bins");
    k.rBins = uint32_t(rBins);
    k.zBins = uint32_t(zBins);
    try {
        k.depthAmplitude = get("depth_amplitude_mW_per_mm2").get<std::vector<double>>();
        k.depthRadius = get("depth_radius_um").get<std::vector<double>>();
        for (double& r : k.depthRadius) r /= UM;
        const nlohmann::json& rows = get("intensity_mW_per_mm2");
        if (!rows.is_array() || rows.size() != k.zBins)
            throw InputError("expected " + std::to_string(k.zBins) + " rows", file,
                             "intensity_mW_per_mm2");
        k.intensity.reserve(size_t(k.rBins) * k.zBins);
        for (const auto& row : rows) {
            auto values = row.get<std::vector<float>>();
            if (values.size() != k.rBins)
                throw InputError("every row needs " + std::to_string(k.rBins) + " values", file,
                                 "intensity_mW_per_mm2");
            k.intensity.insert(k.intensity.end(), values.begin(), values.end());
        }
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed array: ") + e.what(), file, "intensity_mW_per_mm2");
    }
    if (k.depthAmplitude.size() != k.zBins || k.depthRadius.size() != k.zBins)
        throw InputError("depth profiles need one value per depth slice", file,
                         "depth_amplitude_mW_per_mm2");
    if (k.fit.we3d > 0 && k.fit.de3d > 0 && k.mua > 0) computeFitEnergies(k);  // derived fields
    return k;
}

void BeamKernel::save(const std::string& path) const {
    writeFileAtomic(path, toJson().dump(1) + "\n");
}

BeamKernel BeamKernel::load(const std::string& path) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(readFile(path));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("not valid JSON: ") + e.what(), path);
    }
    return fromJson(j, path);
}

BeamKernel kernelFromMonteCarlo(const transport::McResult& mc, double power) {
    const transport::McSetup& s = mc.setup;
    if (!(s.optics.mua > 0))
        throw InputError(
            "the beam kernel needs mua > 0: Eq. 11 converts absorbed power to intensity by "
            "dividing by mua",
            "", "mua");
    if (!(power > 0)) throw InputError("beam power must be > 0", "", "power");
    if (s.beam != transport::BeamShape::Gaussian || !(s.w0 > 0))
        throw InputError("the beam kernel needs a Gaussian beam with W0 > 0", "", "w0");
    BeamKernel k;
    k.power = power;
    k.w0 = s.w0;
    k.mua = s.optics.mua;
    k.specularReflectance = mc.specular().value;
    k.diffuseReflectance = mc.diffuse().value;
    k.photons = mc.total().photons;
    k.rBins = s.bins.rBins;
    k.zBins = s.bins.zBins;
    k.rBin = s.bins.rMax / s.bins.rBins;
    k.zBin = s.bins.zMax / s.bins.zBins;
    k.intensity.resize(size_t(k.rBins) * k.zBins);
    const double launched = double(mc.launched());
    for (uint32_t iz = 0; iz < k.zBins; ++iz)
        for (uint32_t ir = 0; ir < k.rBins; ++ir) {
            double r0 = ir * k.rBin, r1 = (ir + 1) * k.rBin;
            double volume = PI * (r1 * r1 - r0 * r0) * k.zBin;
            size_t i = size_t(iz) * k.rBins + ir;
            double absorbedPower = power * double(mc.absorbedRZ[i]) / launched;  // mW
            k.intensity[i] = float(absorbedPower / volume / k.mua);
        }
    fitKernel(k);
    return k;
}

double kernelTableRadius(double w0) {
    return 4 * w0;
}

transport::McSetup kernelSetup(const optics::MediumOptics& optics, double w0, double thickness) {
    transport::McSetup setup;
    setup.optics = optics;
    setup.beam = transport::BeamShape::Gaussian;
    setup.w0 = w0;
    setup.thickness = thickness;
    setup.bins.rMax = kernelTableRadius(w0);
    setup.bins.zMax = optics.mua > 0 ? 3.0 / optics.mua : 1.0;
    if (thickness > 0) setup.bins.zMax = std::min(setup.bins.zMax, thickness);
    setup.bins.rBins = setup.bins.zBins = 80;
    // The kernel is built from the bins alone: the reflectance's control variates would cost
    // time and change no bin.
    setup.controlVariates = false;
    return setup;
}

}  // namespace vpsim::kernel
