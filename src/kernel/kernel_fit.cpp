// Fits of the tabulated beam intensity: a Gaussian across r in every depth slice (seed 000
// Fig. 12), the depth zmax of the sub-surface maximum, and the separable model of Eq. 12 below it.
// All fits are weighted linear least squares on log I (closed form, no iteration to diverge):
// log I is linear in the unknowns (ln amplitude, 2/We^2, 1/De) for both models.

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "vpsim/core/error.h"
#include "vpsim/kernel/beam_kernel.h"

namespace vpsim::kernel {

namespace {

/// Bins below this fraction of the relevant maximum are left out of the fits: their log is
/// dominated by photon noise and by the non-Gaussian scattering halo.
constexpr double SIGNAL_FRACTION = 0.05;

constexpr double PI = 3.14159265358979323846;

double ringVolume(const BeamKernel& k, uint32_t ir) {
    double r0 = ir * k.rBin, r1 = (ir + 1) * k.rBin;
    return PI * (r1 * r1 - r0 * r0) * k.zBin;
}

double rCentre(const BeamKernel& k, uint32_t ir) {
    return (ir + 0.5) * k.rBin;
}
double zCentre(const BeamKernel& k, uint32_t iz) {
    return (iz + 0.5) * k.zBin;
}

/// Gaussian Ie(0,z) exp(-2 r^2 / We^2) through one slice; false when the slice has no usable
/// signal.
bool fitSlice(const BeamKernel& k, uint32_t iz, double& amplitude, double& radius) {
    const float* row = k.intensity.data() + size_t(iz) * k.rBins;
    double peak = *std::max_element(row, row + k.rBins);
    if (!(peak > 0)) return false;
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    int used = 0;
    for (uint32_t ir = 0; ir < k.rBins; ++ir) {
        double value = row[ir];
        if (!(value > SIGNAL_FRACTION * peak)) continue;
        double w = value * ringVolume(k, ir);  // ~ photon count: inverse variance of log I
        Eigen::Vector2d x(1.0, rCentre(k, ir) * rCentre(k, ir));
        normal += w * x * x.transpose();
        rhs += w * std::log(value) * x;
        ++used;
    }
    if (used < 3) return false;
    Eigen::Vector2d c = normal.ldlt().solve(rhs);
    if (!(c[1] < 0) || !std::isfinite(c[0])) return false;
    amplitude = std::exp(c[0]);
    radius = std::sqrt(-2.0 / c[1]);
    return true;
}

/// Depth of the largest Ie(0, z), resolved below the bin size. When the first slice is the
/// largest, the bin-averaged intensity falls from the surface and no sub-surface maximum is
/// resolved: zmax is exactly 0 (seed 000's Eq. 14 then uses the whole layer). Otherwise log
/// Ie(0, z) over the slices within 2 of the largest is fitted by a least-squares parabola (exact
/// for a Gaussian-like peak; bin averaging does not move the vertex of a parabola) and zmax is its
/// vertex, kept inside the fitted window; the centre of the largest slice when the fit is
/// degenerate (not concave, or fewer than 3 usable slices).
double depthOfMaximum(const BeamKernel& k) {
    const auto& a = k.depthAmplitude;
    const int n = int(a.size());
    const int top = int(std::max_element(a.begin(), a.end()) - a.begin());
    if (top == 0) return 0.0;
    const int lo = std::max(0, top - 2), hi = std::min(n - 1, top + 2);
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    int used = 0;
    for (int i = lo; i <= hi; ++i) {
        if (!(a[size_t(i)] > 0)) continue;
        const double z = i + 0.5 - top;  // in bins, centred for conditioning
        Eigen::Vector3d x(1.0, z, z * z);
        normal += x * x.transpose();
        rhs += std::log(a[size_t(i)]) * x;
        ++used;
    }
    double centre = top + 0.5;
    if (used >= 3) {
        const Eigen::Vector3d c = normal.ldlt().solve(rhs);
        if (c.allFinite() && c[2] < 0)
            centre = std::clamp(top - c[1] / (2 * c[2]), double(lo), hi + 1.0);
    }
    return centre * k.zBin;
}

/// Power (mW) the Eq. 12 model absorbs over the table's region: mua A (pi We^2 / 2)
/// (1 - exp(-2 R^2 / We^2)) De (1 - exp(-Z / De)), from the closed-form integrals.
double modelPower(const BeamKernel& k, const KernelFit& f) {
    const double rMax = k.rBin * k.rBins, zMax = k.zBin * k.zBins;
    const double radial =
        0.5 * PI * f.we3d * f.we3d * -std::expm1(-2 * rMax * rMax / (f.we3d * f.we3d));
    const double depth = f.de3d * -std::expm1(-zMax / f.de3d);
    return k.mua * f.amplitude * radial * depth;
}

}  // namespace

/// Energy carried by the fit, and the energy-conserving variant with its residual.
void computeFitEnergies(BeamKernel& k) {
    double table = 0;
    for (uint32_t iz = 0; iz < k.zBins; ++iz)
        for (uint32_t ir = 0; ir < k.rBins; ++ir)
            table += double(k.intensity[size_t(iz) * k.rBins + ir]) * ringVolume(k, ir);
    table *= k.mua;  // mW
    k.tableAbsorbedFraction = k.power > 0 ? table / k.power : 0.0;
    k.fit.energyFraction = table > 0 ? modelPower(k, k.fit) / table : 0.0;
    k.energyFit = k.fit;
    k.energyFit.energyFraction = 1.0;
    if (k.fit.energyFraction > 0) k.energyFit.amplitude = k.fit.amplitude / k.fit.energyFraction;
    const uint32_t first = std::min(uint32_t(k.fit.fitDepthStart / k.zBin), k.zBins - 1);
    double misfit = 0, norm = 0;
    const double scale = k.energyFit.amplitude / k.fit.amplitude;
    for (uint32_t iz = first; iz < k.zBins; ++iz)
        for (uint32_t ir = 0; ir < k.rBins; ++ir) {
            double value = k.intensity[size_t(iz) * k.rBins + ir];
            double model = scale * k.fitted(rCentre(k, ir), zCentre(k, iz));
            misfit += ringVolume(k, ir) * (value - model) * (value - model);
            norm += ringVolume(k, ir) * value * value;
        }
    k.energyFit.residual = norm > 0 ? std::sqrt(misfit / norm) : 0.0;
}

void fitKernel(BeamKernel& k) {
    if (k.rBins == 0 || k.zBins == 0 || k.intensity.size() != size_t(k.rBins) * k.zBins)
        throw InputError("beam kernel table is empty or inconsistent", "", "intensity");
    k.depthAmplitude.assign(k.zBins, 0.0);
    k.depthRadius.assign(k.zBins, 0.0);
    bool any = false;
    for (uint32_t iz = 0; iz < k.zBins; ++iz)
        any |= fitSlice(k, iz, k.depthAmplitude[iz], k.depthRadius[iz]);
    if (!any)
        throw InputError("beam kernel table holds no usable intensity (too few photons or bins?)",
                         "", "intensity");
    k.zmax = depthOfMaximum(k);

    // Eq. 12 over the slices from the one holding zmax down.
    const uint32_t first = std::min(uint32_t(k.zmax / k.zBin), k.zBins - 1);
    k.fit.fitDepthStart = zCentre(k, first);
    double peak = 0;
    for (size_t i = size_t(first) * k.rBins; i < k.intensity.size(); ++i)
        peak = std::max(peak, double(k.intensity[i]));
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    int used = 0;
    for (uint32_t iz = first; iz < k.zBins; ++iz)
        for (uint32_t ir = 0; ir < k.rBins; ++ir) {
            double value = k.intensity[size_t(iz) * k.rBins + ir];
            if (!(value > SIGNAL_FRACTION * peak)) continue;
            double w = value * ringVolume(k, ir);
            double r = rCentre(k, ir);
            Eigen::Vector3d x(1.0, -r * r, -zCentre(k, iz));
            normal += w * x * x.transpose();
            rhs += w * std::log(value) * x;
            ++used;
        }
    Eigen::Vector3d c =
        used >= 4 ? Eigen::Vector3d(normal.ldlt().solve(rhs)) : Eigen::Vector3d::Zero();
    if (!(c[1] > 0) || !(c[2] > 0) || !std::isfinite(c[0]))
        throw InputError(
            "cannot fit Eq. 12: the intensity does not fall off in r and z over the tallied "
            "region (enlarge r_max/z_max or launch more photons)",
            "", "intensity");
    k.fit.amplitude = std::exp(c[0]);
    k.fit.we3d = std::sqrt(2.0 / c[1]);
    k.fit.de3d = 1.0 / c[2];

    double misfit = 0, norm = 0;
    for (uint32_t iz = first; iz < k.zBins; ++iz)
        for (uint32_t ir = 0; ir < k.rBins; ++ir) {
            double value = k.intensity[size_t(iz) * k.rBins + ir];
            double model = k.fitted(rCentre(k, ir), zCentre(k, iz));
            double v = ringVolume(k, ir);
            misfit += v * (value - model) * (value - model);
            norm += v * value * value;
        }
    k.fit.residual = norm > 0 ? std::sqrt(misfit / norm) : 0.0;
    computeFitEnergies(k);
}

}  // namespace vpsim::kernel
