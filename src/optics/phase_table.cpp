// Phase-function CDF on fine theta panels and its inverse (seed 000 Eq. 5).

#include "vpsim/optics/phase_table.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"

namespace vpsim::optics {
namespace {

constexpr double PI = 3.14159265358979323846;

// 4-point Gauss-Legendre nodes and weights on [-1, 1] (Abramowitz & Stegun 25.4.30).
constexpr double GL_NODES[4] = {-0.861136311594052575, -0.339981043584856265, 0.339981043584856265,
                                0.861136311594052575};
constexpr double GL_WEIGHTS[4] = {0.347854845137453857, 0.652145154862546143, 0.652145154862546143,
                                  0.347854845137453857};

}  // namespace

double phasePanelWidth(int terms) {
    return std::min(MAX_PHASE_PANEL_WIDTH, PI / (2.0 * std::max(terms, 1)));
}

ThetaQuadrature makeThetaQuadrature(double maxPanelWidth) {
    if (!(maxPanelWidth > 0.0)) throw InputError("phase panel width must be positive");
    ThetaQuadrature q;
    const int panels = static_cast<int>(std::ceil(PI / maxPanelWidth - 1e-9));
    const double width = PI / panels;
    q.edges.resize(static_cast<size_t>(panels) + 1);
    for (int p = 0; p <= panels; ++p) q.edges[static_cast<size_t>(p)] = p * width;
    q.edges.back() = PI;
    q.nodeMu.reserve(static_cast<size_t>(panels) * 4);
    q.nodeWeight.reserve(static_cast<size_t>(panels) * 4);
    for (int p = 0; p < panels; ++p) {
        const double mid = (p + 0.5) * width, half = 0.5 * width;
        for (int j = 0; j < 4; ++j) {
            const double theta = mid + half * GL_NODES[j];
            q.nodeMu.push_back(std::cos(theta));
            q.nodeWeight.push_back(2.0 * PI * std::sin(theta) * half * GL_WEIGHTS[j]);
        }
    }
    return q;
}

PhaseTable buildPhaseTable(const ThetaQuadrature& quadrature, const std::vector<double>& kAtNodes,
                           int tableSize) {
    if (kAtNodes.size() != quadrature.nodeMu.size())
        throw InputError("phase table: " + std::to_string(kAtNodes.size()) + " values for " +
                         std::to_string(quadrature.nodeMu.size()) + " quadrature nodes");
    if (tableSize < 2) throw InputError("phase table size must be at least 2");
    PhaseTable t;
    t.thetaEdges = quadrature.edges;
    const int panels = quadrature.panelCount();
    const int perPanel = quadrature.nodesPerPanel;
    t.cdf.assign(static_cast<size_t>(panels) + 1, 0.0);
    double total = 0.0, moment = 0.0;
    for (int p = 0; p < panels; ++p) {
        double panel = 0.0;
        for (int j = 0; j < perPanel; ++j) {
            const size_t i = static_cast<size_t>(p * perPanel + j);
            const double w = kAtNodes[i] * quadrature.nodeWeight[i];
            panel += w;
            moment += w * quadrature.nodeMu[i];
        }
        total += panel;
        t.cdf[static_cast<size_t>(p) + 1] = total;
    }
    if (!(total > 0.0) || !std::isfinite(total))
        throw InputError("phase table: the phase function has no positive finite weight");
    for (double& v : t.cdf) v /= total;
    t.cdf.back() = 1.0;
    t.integral = total;
    t.meanCosine = moment / total;

    // Invert: for each u find the panel holding it and interpolate theta linearly inside it.
    t.inverseCdf.resize(static_cast<size_t>(tableSize));
    size_t panel = 0;
    for (int i = 0; i < tableSize; ++i) {
        const double u = static_cast<double>(i) / (tableSize - 1);
        while (panel + 1 < static_cast<size_t>(panels) && t.cdf[panel + 1] < u) ++panel;
        const double c0 = t.cdf[panel], c1 = t.cdf[panel + 1];
        const double f = (c1 > c0) ? std::clamp((u - c0) / (c1 - c0), 0.0, 1.0) : 0.0;
        const double theta =
            t.thetaEdges[panel] + f * (t.thetaEdges[panel + 1] - t.thetaEdges[panel]);
        t.inverseCdf[static_cast<size_t>(i)] = static_cast<float>(std::cos(theta));
    }
    t.inverseCdf.front() = 1.0f;
    t.inverseCdf.back() = -1.0f;
    return t;
}

double PhaseTable::cdfAt(double theta) const {
    if (theta <= 0.0) return 0.0;
    if (theta >= thetaEdges.back()) return 1.0;
    auto it = std::upper_bound(thetaEdges.begin(), thetaEdges.end(), theta);
    const size_t hi = static_cast<size_t>(it - thetaEdges.begin()), lo = hi - 1;
    const double f = (theta - thetaEdges[lo]) / (thetaEdges[hi] - thetaEdges[lo]);
    return cdf[lo] + f * (cdf[hi] - cdf[lo]);
}

double PhaseTable::tableMeanCosine() const {
    const size_t n = inverseCdf.size();
    if (n < 2) return 0.0;
    double sum = 0.0;
    for (size_t i = 0; i + 1 < n; ++i)
        sum += 0.5 * (double(inverseCdf[i]) + double(inverseCdf[i + 1]));
    return sum / static_cast<double>(n - 1);
}

double PhaseTable::sampleCosine(double u) const {
    const double position = std::clamp(u, 0.0, 1.0) * static_cast<double>(inverseCdf.size() - 1);
    const size_t i = std::min(static_cast<size_t>(position), inverseCdf.size() - 2);
    const double f = position - static_cast<double>(i);
    return (1.0 - f) * inverseCdf[i] + f * inverseCdf[i + 1];
}

std::vector<double> phaseIntensityAtNodes(const MieCoefficients& c,
                                          const ThetaQuadrature& quadrature) {
    return miePhaseIntensity(c, quadrature.nodeMu);
}

PhaseTable miePhaseTable(const MieCoefficients& c, int tableSize) {
    ThetaQuadrature q = makeThetaQuadrature(phasePanelWidth(c.terms()));
    return buildPhaseTable(q, phaseIntensityAtNodes(c, q), tableSize);
}

}  // namespace vpsim::optics
