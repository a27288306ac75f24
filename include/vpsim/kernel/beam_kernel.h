#pragma once
/// @file
/// The beam kernel: intensity I(r, z) of one stationary beam in the material, estimated from the
/// photon Monte Carlo (seed 000 Eq. 11), tabulated on cylindrical bins, and fitted by the
/// separable model of Eq. 12,
///   Ie3D(r, z) = Ie3D(0, 0) exp(-2 r^2 / We3D^2) exp(-z / De3D),
/// which the planners and the exposure stage use (or the table, which keeps the sub-surface
/// maximum that Eq. 12 smooths away).

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/transport/photon_mc.h"

namespace vpsim::kernel {

/// Eq. 12 fitted to the tabulated intensity at depths z >= fitDepthStart (= zmax: above the
/// sub-surface maximum the field is not Beer-Lambert-like, seed 000 Fig. 12-13).
struct KernelFit {
    double amplitude = 0.0;      ///< Ie3D(0, 0), mW/mm^2
    double we3d = 0.0;           ///< Gaussian 1/e^2 radius We3D, mm
    double de3d = 0.0;           ///< penetration depth De3D, mm
    double fitDepthStart = 0.0;  ///< first depth used by the fit, mm
    /// Relative RMS misfit over the bins used, volume weighted: sqrt(sum V (I-F)^2 / sum V I^2).
    double residual = 0.0;
    /// Power the model absorbs over the table's region (z from 0, r up to the table's radius)
    /// over the power the table absorbs there (mua x sum of I x bin volume).
    double energyFraction = 0.0;
};

/// Tabulated and fitted intensity of one beam. Depth z from the surface, r from the beam axis.
struct BeamKernel {
    double power = 0.0;                ///< incident beam power, mW
    double w0 = 0.0;                   ///< incident Gaussian 1/e^2 radius W0, mm
    double mua = 0.0;                  ///< absorption coefficient used for Eq. 11, 1/mm
    double specularReflectance = 0.0;  ///< fraction reflected at entry
    double diffuseReflectance = 0.0;   ///< fraction scattered back out of the surface
    uint64_t photons = 0;              ///< photons behind the estimate
    double rBin = 0.0, zBin = 0.0;     ///< bin sizes, mm
    uint32_t rBins = 0, zBins = 0;
    /// I(r, z) averaged over each bin, mW/mm^2, [iz * rBins + ir]; bin centres at
    /// ((ir + 0.5) rBin, (iz + 0.5) zBin).
    std::vector<float> intensity;
    /// Per depth slice iz, the Gaussian fitted across r: Ie(0, z) in mW/mm^2 and We(z) in mm
    /// (seed 000 Fig. 12); 0 where a slice has too little signal.
    std::vector<double> depthAmplitude, depthRadius;
    double zmax = 0.0;  ///< depth of the largest Ie(0, z), mm (0 when it falls from the surface)
    /// The Eq. 12 fit the planners and the fitted engine use: weighted least squares on log I
    /// below zmax, which matches the intensity where the cure front lies; it carries
    /// fit.energyFraction of the table's absorbed power (the rest is in the near-surface peak and
    /// the wide scattering halo that a Gaussian x exponential cannot hold).
    KernelFit fit;
    /// The same We3D and De3D with the amplitude scaled so that the model absorbs exactly the
    /// table's power (energyFraction 1): reported for comparison, not used by the engines.
    KernelFit energyFit;
    /// Power absorbed in the table's region over the incident power (no unit).
    double tableAbsorbedFraction = 0.0;

    /// Table value at (r, z), bilinear between bin centres (nearest at the edges), 0 outside.
    double sample(double r, double z) const;
    /// The Eq. 12 model at (r, z), mW/mm^2.
    double fitted(double r, double z) const;
    /// Intensity without scattering (Beer-Lambert of the same beam, same entry loss), mW/mm^2.
    double beerLambert(double r, double z) const;

    nlohmann::json toJson() const;
    /// @throw InputError naming `file` and the key when a field is missing or inconsistent.
    static BeamKernel fromJson(const nlohmann::json& json, const std::string& file = "");
    /// Writes JSON atomically. @throw InputError when the file cannot be written.
    void save(const std::string& path) const;
    /// @throw InputError for a missing, malformed or inconsistent file.
    static BeamKernel load(const std::string& path);
};

/// The radius (mm) of a beam kernel's table for a beam of 1/e^2 radius w0: 4 w0, where the
/// Gaussian is 1e-14 (kernelSetup's bins; the tabulated engine's stencils reach no further).
double kernelTableRadius(double w0);

/// The Monte Carlo setup of a beam kernel: a Gaussian beam of 1/e^2 radius w0 (mm) into the
/// medium (a slab of `thickness` mm, or semi-infinite when 0), tallied on 80 x 80 bins 4 w0 wide
/// (the Gaussian is 1e-14 there) and 3 absorption lengths deep (or the slab's thickness). The
/// caller sets photons and seed and may override the bins.
transport::McSetup kernelSetup(const optics::MediumOptics& optics, double w0,
                               double thickness = 0.0);

/// Eq. 11: absorbed power per bin volume divided by mua is the local intensity (fluence rate).
/// This equals the seed's ratio Ii(0,0,0)/rho_ns(0,0,0), which for the unscattered beam is 1/mua.
/// Fills the table and runs fitKernel.
/// @param power incident power, mW
/// @throw InputError when mua is 0 (Eq. 11 divides by it) or power/W0 are not positive.
BeamKernel kernelFromMonteCarlo(const transport::McResult& mc, double power);

/// Fits each depth slice (We(z), Ie(0,z)), finds zmax (sub-bin, see kernel_fit.cpp), and fits
/// Eq. 12 below zmax, by weighted linear least squares on the logarithm (weights = bin volume x
/// intensity, i.e. proportional to the photon count of the bin, the inverse variance of log I)
/// over bins above 5% of the maximum; then the energies of that fit and of the
/// energy-conserving variant (energyFit).
/// @throw InputError when the table is empty or holds no usable signal.
void fitKernel(BeamKernel& kernel);

/// Fills fit.energyFraction, energyFit and tableAbsorbedFraction from the table and fit (called
/// by fitKernel, and when loading a kernel file written before these fields existed).
void computeFitEnergies(BeamKernel& kernel);

/// Saves the kernel revolved about the axis onto a Cartesian grid of voxel rBin as OpenVDB float
/// grids "intensity" (MC) and "intensity_no_scattering" (Beer-Lambert), mW/mm^2, in mm.
/// @throw ResourceError above 32M voxels; InputError when the file cannot be written.
void writeKernelVdb(const std::string& path, const BeamKernel& kernel);

/// Writes the figures of seed 000 Fig. 11-13 into `directory`, each as .svg and .png through the
/// plotting layer (plot/plot.h): intensity_scattered, intensity_no_scattering, intensity_fit
/// (maps of I(r, z) in mW/mm^2 on one scale, r mirrored, depth down, the same iso-intensity
/// contours); contours_scattering (Fig. 11: contours with and without scattering), contours_fit
/// (Fig. 13: the table against the Eq. 12 fit), amplitude_vs_depth and radius_vs_depth (Fig. 12:
/// Ie(0, z) and We(z), zmax marked); axes in um.
/// @throw InputError when a file cannot be written.
void writeKernelFigures(const std::string& directory, const BeamKernel& kernel);

}  // namespace vpsim::kernel
