#include "vpsim/optics/mie_summary.h"

#include <cmath>
#include <cstdio>

#include "vpsim/core/error.h"

namespace vpsim::optics {
namespace {

constexpr double PI = 3.14159265358979323846;
constexpr double MM_TO_UM = 1000.0;

nlohmann::json complexJson(Complex z) {
    return nlohmann::json::array({z.real(), z.imag()});
}

/// Adds qext/qsca/qback/g and, for the requested angles, s1/s2 lists of [re, im].
void addSphere(nlohmann::json& out, const MieCoefficients& c, const MieEfficiencies& e,
               const std::vector<double>& angles) {
    out["qext"] = e.qext;
    out["qsca"] = e.qsca;
    out["qabs"] = e.qabs;
    out["qback"] = e.qback;
    out["g"] = e.g;
    out["terms"] = c.terms();
    if (angles.empty()) return;
    out["angles_deg"] = angles;
    nlohmann::json s1 = nlohmann::json::array(), s2 = nlohmann::json::array();
    for (double a : angles) {
        MieAmplitudes s = mieAmplitudes(c, std::cos(a * PI / 180.0));
        s1.push_back(complexJson(s.s1));
        s2.push_back(complexJson(s.s2));
    }
    out["s1"] = s1;
    out["s2"] = s2;
}

}  // namespace

void checkAngles(const std::vector<double>& angles, const std::string& option) {
    for (double a : angles)
        if (!(a >= 0.0 && a <= 180.0)) {
            char text[32];
            std::snprintf(text, sizeof text, "%g", a);
            throw InputError(option + ": angles must be in [0, 180] degrees, got " + text);
        }
}

nlohmann::json mieSphereJson(Complex m, double x, const std::vector<double>& anglesDeg) {
    checkAngles(anglesDeg, "angles");
    checkMieInput(m, x);
    MieCoefficients c = mieCoefficients(m, x);
    nlohmann::json out;
    out["x"] = x;
    out["m"] = complexJson(m);
    addSphere(out, c, mieEfficiencies(c), anglesDeg);
    return out;
}

nlohmann::json slurryOpticsJson(const SlurryOptics& s, const std::vector<double>& anglesDeg,
                                const std::vector<double>& cdfAnglesDeg) {
    checkAngles(anglesDeg, "angles");
    checkAngles(cdfAnglesDeg, "cdf angles");
    nlohmann::json out;
    out["x"] = s.x;
    out["m"] = complexJson(s.m);
    // S1/S2 are those of a sphere of the nominal radius; efficiencies are ensemble averages.
    MieCoefficients nominal = mieCoefficients(s.m, s.x);
    addSphere(out, nominal, s.efficiencies, anglesDeg);
    out["terms"] = nominal.terms();
    out["scattering_mean_free_path_um"] = s.scatteringMeanFreePath * MM_TO_UM;
    out["transport_mean_free_path_um"] = s.transportMeanFreePath * MM_TO_UM;
    out["mus_per_mm"] = s.medium.mus;
    out["mua_per_mm"] = s.medium.mua;
    out["phase_table_size"] = s.phase.inverseCdf.size();
    out["phase_table_mean_cosine"] = s.phase.tableMeanCosine();
    if (!cdfAnglesDeg.empty()) {
        nlohmann::json cdf = nlohmann::json::array();
        for (double a : cdfAnglesDeg) cdf.push_back(s.phase.cdfAt(a * PI / 180.0));
        out["cdf_angles_deg"] = cdfAnglesDeg;
        out["cdf"] = cdf;
    }
    return out;
}

}  // namespace vpsim::optics
