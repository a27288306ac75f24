#pragma once
/// @file
/// Tabulated scattering phase function (seed 000 Eq. 5) and its inverse CDF for sampling.
/// The CDF of the polar angle is integrated on theta panels no wider than 0.1 degree (and
/// narrower for large spheres, whose lobes are ~pi/N wide) with Gauss-Legendre nodes, then
/// inverted onto a uniform table in u as MediumOptics::inverseCdf expects.

#include <vector>

#include "vpsim/optics/mie.h"

namespace vpsim::optics {

/// Widest theta panel used for phase-function CDFs: 0.1 degree, in radians.
constexpr double MAX_PHASE_PANEL_WIDTH = 0.1 * 3.14159265358979323846 / 180.0;

/// Default number of entries of an inverse-CDF table.
constexpr int DEFAULT_PHASE_TABLE_SIZE = 4096;

/// Panels in theta on [0, pi] with Gauss-Legendre nodes inside each.
struct ThetaQuadrature {
    std::vector<double> edges;  ///< panel edges, rad, edges[0] = 0, back() = pi
    int nodesPerPanel = 4;
    std::vector<double> nodeMu;      ///< cos(theta) at the nodes, panel by panel
    std::vector<double> nodeWeight;  ///< solid-angle weight 2 pi sin(theta) dtheta of each node, sr
    int panelCount() const { return static_cast<int>(edges.size()) - 1; }
};

/// Panels of equal width <= maxPanelWidth (rad) covering [0, pi].
/// @throw InputError when maxPanelWidth is not positive
ThetaQuadrature makeThetaQuadrature(double maxPanelWidth = MAX_PHASE_PANEL_WIDTH);

/// Panel width for a sphere with `terms` Mie terms: min(0.1 deg, pi / (2 terms)).
double phasePanelWidth(int terms);

/// A phase function tabulated for sampling.
struct PhaseTable {
    std::vector<double> thetaEdges;  ///< panel edges, rad
    std::vector<double> cdf;         ///< P(theta' < theta) at the edges, 0 .. 1
    double integral = 0.0;           ///< integral of K over the sphere (pi x^2 Qsca for one sphere)
    double meanCosine = 0.0;         ///< <cos theta> of the phase function by the same quadrature
    /// cos(theta) at u = i/(n-1), from +1 (u = 0) to -1 (u = 1), linear in u between entries.
    std::vector<float> inverseCdf;

    /// CDF of the polar angle at theta (rad), linear between panel edges.
    double cdfAt(double theta) const;
    /// Mean of cos(theta) over u for the table with linear interpolation (what sampling gives).
    double tableMeanCosine() const;
    /// cos(theta) for a uniform u in [0,1] from the table, as the Monte Carlo samples it.
    double sampleCosine(double u) const;
};

/// Builds the CDF and its inverse from K sampled at the nodes of `quadrature`.
/// @param kAtNodes K(theta) >= 0 at every node (any normalisation)
/// @param tableSize entries of the inverse CDF, >= 2
/// @throw InputError on a size mismatch, a table size < 2 or a phase function without weight
PhaseTable buildPhaseTable(const ThetaQuadrature& quadrature, const std::vector<double>& kAtNodes,
                           int tableSize = DEFAULT_PHASE_TABLE_SIZE);

/// K = (|S1|^2+|S2|^2)/2 of one sphere at the quadrature nodes.
std::vector<double> phaseIntensityAtNodes(const MieCoefficients& c,
                                          const ThetaQuadrature& quadrature);

/// Phase table of one sphere on panels of phasePanelWidth(c.terms()).
PhaseTable miePhaseTable(const MieCoefficients& c, int tableSize = DEFAULT_PHASE_TABLE_SIZE);

}  // namespace vpsim::optics
