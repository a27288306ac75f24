// Slurry optics from Mie theory (seed 000 Section II, Eq. 5, 8, 9, 10). See slurry.h for how the
// seed is read.

#include "vpsim/optics/slurry.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vpsim/core/error.h"

namespace vpsim::optics {
namespace {

constexpr double PI = 3.14159265358979323846;
/// Random close packing of equal spheres is ~0.64 and the densest packing 0.7405: a solid
/// fraction at or above 0.74 cannot be a slurry.
constexpr double MAX_VOLUME_FRACTION = 0.74;

struct RadiusNode {
    double radius;  ///< mm
    double weight;  ///< number fraction, sums to 1
};

std::vector<RadiusNode> radiusNodes(const SlurrySpec& spec) {
    if (spec.size.kind == SizeDistribution::Kind::Monodisperse || spec.size.sigmaG == 1.0)
        return {{spec.radius, 1.0}};
    const double lnSigma = std::log(spec.size.sigmaG);
    const int n = spec.size.points;
    std::vector<RadiusNode> nodes;
    double total = 0.0;
    for (int j = 0; j < n; ++j) {
        const double t = -6.0 + 12.0 * j / (n - 1);  // standard normal variable of ln r
        double w = std::exp(-0.5 * t * t);
        if (j == 0 || j == n - 1) w *= 0.5;  // trapezoid rule
        nodes.push_back({spec.radius * std::exp(t * lnSigma), w});
        total += w;
    }
    for (auto& node : nodes) node.weight /= total;
    return nodes;
}

std::string describe(double value) {
    std::ostringstream s;
    s << value;
    return s.str();
}

}  // namespace

void validateSlurrySpec(const SlurrySpec& s) {
    auto positive = [](double v, const char* what, const char* unit) {
        if (!(v > 0.0) || !std::isfinite(v))
            throw InputError(std::string(what) + " must be positive, got " + describe(v) + " " +
                             unit);
    };
    positive(s.wavelength, "wavelength", "mm");
    positive(s.resinIndex, "resin refractive index", "");
    positive(s.resinPenetrationDepth, "resin penetration depth", "mm");
    positive(s.radius, "particle radius", "mm");
    if (!(s.particleIndex.real() > 0.0) || !std::isfinite(s.particleIndex.real()))
        throw InputError("particle refractive index must have a positive real part, got " +
                         formatRefractiveIndex(s.particleIndex));
    if (s.particleIndex.imag() > 0.0)
        throw InputError("particle refractive index " + formatRefractiveIndex(s.particleIndex) +
                         " has a positive imaginary part; vpsim uses n - ik (e.g. 1.75-0.001i)");
    if (!(s.volumeFraction > 0.0 && s.volumeFraction < MAX_VOLUME_FRACTION))
        throw InputError(
            "volume fraction must be in (0, 0.74) (0.74 is the densest packing of "
            "spheres), got " +
            describe(s.volumeFraction));
    if (s.size.kind == SizeDistribution::Kind::LogNormal) {
        if (!(s.size.sigmaG >= 1.0) || s.size.sigmaG > 5.0)
            throw InputError("log-normal sigma_g must be in [1, 5], got " +
                             describe(s.size.sigmaG));
        if (s.size.points < 8 || s.size.points > 4096)
            throw InputError("log-normal quadrature points must be in [8, 4096], got " +
                             std::to_string(s.size.points));
    }
    if (s.phaseTableSize < 2 || s.phaseTableSize > (1 << 22))
        throw InputError("phase table size must be in [2, 4194304], got " +
                         std::to_string(s.phaseTableSize));
    // Particles index-matched to the resin are invisible: Mie theory gives Qsca = 0 and there is
    // no phase function. Say so instead of failing later on an empty phase table.
    const Complex relative = s.particleIndex / s.resinIndex;
    if (std::abs(relative - Complex(1.0, 0.0)) < 1e-9)
        throw InputError("particle refractive index " + formatRefractiveIndex(s.particleIndex) +
                         " equals the resin's (" + describe(s.resinIndex) +
                         "): the particles do not scatter, so there is no slurry to model "
                         "(give the resin alone as bulk optics with mus = 0)");
    const double k = 2.0 * PI * s.resinIndex / s.wavelength;
    double largest = s.radius;
    for (const auto& node : radiusNodes(s)) largest = std::max(largest, node.radius);
    if (k * largest > 2e4)
        throw InputError(
            "size parameter " + describe(k * largest) +
            " is above the supported 20000 (particle much larger than the wavelength)");
}

SlurryOptics computeSlurryOptics(const SlurrySpec& spec) {
    validateSlurrySpec(spec);
    const double k = 2.0 * PI * spec.resinIndex / spec.wavelength;  // wavenumber in the resin, 1/mm
    const Complex m = spec.particleIndex / spec.resinIndex;
    const std::vector<RadiusNode> nodes = radiusNodes(spec);

    std::vector<MieCoefficients> spheres;
    int maxTerms = 1;
    for (const auto& node : nodes) {
        spheres.push_back(mieCoefficients(m, k * node.radius));
        maxTerms = std::max(maxTerms, spheres.back().terms());
    }
    const ThetaQuadrature quadrature = makeThetaQuadrature(phasePanelWidth(maxTerms));

    // Number-weighted averages of cross sections (mm^2), volume (mm^3) and K (dC/dOmega = K/k^2).
    double cext = 0.0, csca = 0.0, cback = 0.0, cscaG = 0.0, area = 0.0, volume = 0.0;
    std::vector<double> kAverage(quadrature.nodeMu.size(), 0.0);
    for (size_t j = 0; j < nodes.size(); ++j) {
        const double r = nodes[j].radius, w = nodes[j].weight;
        const MieEfficiencies e = mieEfficiencies(spheres[j]);
        const double geometric = PI * r * r;
        cext += w * e.qext * geometric;
        csca += w * e.qsca * geometric;
        cback += w * e.qback * geometric;
        cscaG += w * e.qsca * e.g * geometric;
        area += w * geometric;
        volume += w * 4.0 / 3.0 * PI * r * r * r;
        const std::vector<double> kj = phaseIntensityAtNodes(spheres[j], quadrature);
        for (size_t i = 0; i < kj.size(); ++i) kAverage[i] += w * kj[i];
    }

    if (!(csca > 0.0) || !std::isfinite(csca))
        throw InputError("particles of index " + formatRefractiveIndex(spec.particleIndex) +
                         " in resin of index " + describe(spec.resinIndex) +
                         " scatter no light (Qsca = 0): nothing to model as a slurry");
    SlurryOptics out;
    out.x = k * spec.radius;
    out.m = m;
    out.efficiencies.qext = cext / area;
    out.efficiencies.qsca = csca / area;
    out.efficiencies.qabs = (cext - csca) / area;
    out.efficiencies.qback = cback / area;
    out.efficiencies.g = csca > 0.0 ? cscaG / csca : 0.0;
    out.scatteringCrossSection = csca;
    // Eq. 8 generalised: number density N = Phi/<V>, mus = N <Csca>; monodisperse gives
    // mus = 3 Phi Qs / (4 r), i.e. lambda_s = 4 r / (3 Phi Qs).
    const double numberDensity = spec.volumeFraction / volume;  // 1/mm^3
    const double mus = numberDensity * csca;
    const double muaParticles = numberDensity * std::max(0.0, cext - csca);
    const double resinFraction =
        spec.absorptionScaledByResinFraction ? 1.0 - spec.volumeFraction : 1.0;
    out.scatteringMeanFreePath = 1.0 / mus;
    out.transportMeanFreePath = out.scatteringMeanFreePath / (1.0 - out.efficiencies.g);
    out.phase = buildPhaseTable(quadrature, kAverage, spec.phaseTableSize);

    out.medium.mua = resinFraction / spec.resinPenetrationDepth + muaParticles;
    out.medium.mus = mus;
    out.medium.g = out.efficiencies.g;
    out.medium.refractiveIndex = spec.resinIndex;
    out.medium.wavelength = spec.wavelength;
    out.medium.phase = PhaseModel::Tabulated;
    out.medium.inverseCdf = out.phase.inverseCdf;
    return out;
}

}  // namespace vpsim::optics
