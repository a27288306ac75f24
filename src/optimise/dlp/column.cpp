#include "vpsim/optimise/dlp/column.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vpsim/core/checks.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"
#include "vpsim/cure/print_through.h"
#include "vpsim/optimise/solvers/bounded_least_squares.h"

namespace vpsim::optimise {
namespace {

void checkProblem(const DlpColumnProblem& p) {
    requirePositive(p.layerThickness, "DLP column: layer thickness");
    requirePositive(p.rateConstant, "DLP column: rate constant K");
    requirePositive(p.attenuation, "DLP column: attenuation mu");
    requirePositive(p.maxDose, "DLP column: maximum dose");
    if (!(p.gelPoint > 0.0 && p.gelPoint < 1.0))
        throw InputError("DLP column: gel point must lie in (0, 1)");
    if (!(p.targetConversion > 0.0 && p.targetConversion < 1.0))
        throw InputError(
            "DLP column: target conversion must lie in (0, 1) (Eq. 11: Phi = 1 gives phi = -inf)");
    if (!(p.penalty >= 0.0) || !std::isfinite(p.penalty))
        throw InputError("DLP column: the penalty coefficient must be >= 0 (Eq. 12)");
}

struct SolidRun {
    size_t begin, end;  ///< layers [begin, end) are solid
};

double squaredDistance(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
    return sum;
}

std::vector<SolidRun> solidRuns(const std::vector<uint8_t>& solid) {
    std::vector<SolidRun> runs;
    for (size_t k = 0; k < solid.size(); ++k) {
        if (!solid[k]) continue;
        if (runs.empty() || runs.back().end != k) runs.push_back({k, k});
        runs.back().end = k + 1;
    }
    return runs;
}

}  // namespace

double bondingDose(double rateConstant, double attenuation, double gelPoint, double layerThickness,
                   int elementsBetween) {
    requirePositive(attenuation, "DLP column: attenuation mu");
    requirePositive(layerThickness, "DLP column: layer thickness");
    if (elementsBetween < 1) throw InputError("DLP column: n_z must be at least 1");
    return std::exp(attenuation * layerThickness * elementsBetween) *
           cure::fppGelDose(rateConstant, gelPoint);
}

std::vector<double> transmissionMatrix(size_t layers, double layerThickness, double rateConstant,
                                       double attenuation) {
    std::vector<double> t(layers * layers, 0.0);
    for (size_t p = 0; p < layers; ++p)
        for (size_t r = p; r < layers; ++r)
            t[p * layers + r] =
                -rateConstant * std::exp(-attenuation * double(r - p) * layerThickness);
    return t;
}

std::vector<double> applyTransmission(const std::vector<double>& dose, double layerThickness,
                                      double rateConstant, double attenuation) {
    // (T d)_p = -K sum_{r >= p} d_r a^(r-p): the accumulated print-through dose times -K.
    std::vector<double> phi = cure::accumulatedLayerDoses(dose, layerThickness, 1.0 / attenuation);
    for (double& value : phi) value *= -rateConstant;
    return phi;
}

std::vector<double> applyTransmissionTransposed(const std::vector<double>& v, double layerThickness,
                                                double rateConstant, double attenuation) {
    // (T^T v)_r = -K sum_{p <= r} v_p a^(r-p): the same recursion run upwards.
    return Transmission{v.size(), rateConstant, std::exp(-attenuation * layerThickness)}
        .applyTransposed(v);
}

std::vector<double> objectivePhotopolymerisation(const std::vector<uint8_t>& solid,
                                                 double targetConversion, double penalty) {
    const double inside = std::log1p(-targetConversion);  // Eq. 6 / 11
    std::vector<double> target(solid.size());
    for (size_t k = 0; k < solid.size(); ++k) target[k] = solid[k] ? inside : penalty;  // Eq. 12
    return target;
}

bool exposureBounds(const std::vector<uint8_t>& exposed, const std::vector<uint8_t>& solid,
                    const DlpColumnProblem& p, std::vector<double>& lower,
                    std::vector<double>& upper) {
    checkProblem(p);
    if (exposed.size() != solid.size())
        throw InputError("DLP column: exposure pattern and part differ in length");
    lower.assign(solid.size(), 0.0);
    upper.assign(solid.size(), 0.0);
    const double gelDose = cure::fppGelDose(p.rateConstant, p.gelPoint);
    const double perLayer = std::exp(p.attenuation * p.layerThickness);
    bool feasible = true;
    double bonding = gelDose;  // grows by exp(mu Le) per element since the last exposure (Eq. 10)
    bool firstOfRun = true;
    for (size_t k = 0; k < solid.size(); ++k) {
        if (!solid[k]) {
            if (exposed[k])
                throw InputError("DLP column: layer " + std::to_string(k) +
                                 " is exposed outside the part");
            bonding = gelDose;  // the next run counts from its own bottom surface
            firstOfRun = true;
            continue;
        }
        bonding *= perLayer;
        if (!exposed[k]) continue;
        if (firstOfRun && p.bonding == Bonding::OwnLayer) bonding = gelDose * perLayer;
        firstOfRun = false;
        lower[k] = bonding;
        upper[k] = p.maxDose;
        feasible = feasible && bonding <= p.maxDose;
        bonding = gelDose;
    }
    return feasible;
}

DlpColumnResult optimiseColumnDosesForPattern(const std::vector<uint8_t>& solid,
                                              const std::vector<uint8_t>& exposed,
                                              const DlpColumnProblem& p,
                                              const DlpOptimiserOptions& options) {
    std::vector<double> lower, upper;
    if (!exposureBounds(exposed, solid, p, lower, upper))
        throw InputError(
            "DLP column: an exposure in this pattern needs more than the maximum dose to bond (Eq. "
            "10)");
    const std::vector<double> target =
        objectivePhotopolymerisation(solid, p.targetConversion, p.penalty);
    // Step 1/L with L = 2 ||T||_2^2 the gradient's Lipschitz constant; ||T||_2 <= sqrt(||T||_1
    // ||T||_inf)
    // <= K / (1 - a). With convex box constraints, projected descent with this step converges to
    // the global minimum of Eq. 8 for the pattern.
    const double a = std::exp(-p.attenuation * p.layerThickness);
    const double normBound = p.rateConstant / (1.0 - a);
    const double step = 1.0 / (2.0 * normBound * normBound);

    DlpColumnResult result;
    result.dose = lower;  // feasible start: every exposure at its bonding dose
    std::vector<double> residual(solid.size());
    int iteration = 0;
    for (; iteration < options.maxIterations; ++iteration) {
        std::vector<double> phi =
            applyTransmission(result.dose, p.layerThickness, p.rateConstant, p.attenuation);
        for (size_t k = 0; k < phi.size(); ++k) residual[k] = phi[k] - target[k];
        std::vector<double> gradient =
            applyTransmissionTransposed(residual, p.layerThickness, p.rateConstant, p.attenuation);
        double largestChange = 0.0, largestDose = 0.0;
        for (size_t k = 0; k < result.dose.size(); ++k) {
            double before = result.dose[k];
            double stepped = before - step * 2.0 * gradient[k];  // Eq. 9
            result.dose[k] = std::clamp(stepped, lower[k], upper[k]);
            largestChange = std::max(largestChange, std::abs(result.dose[k] - before));
            largestDose = std::max(largestDose, result.dose[k]);
        }
        if (largestChange <= options.tolerance * std::max(largestDose, 1e-300)) {
            result.converged = true;
            ++iteration;
            break;
        }
    }
    result.iterations = iteration;
    std::vector<double> phi =
        applyTransmission(result.dose, p.layerThickness, p.rateConstant, p.attenuation);
    result.objective = squaredDistance(phi, target);
    result.conversion.resize(phi.size());
    for (size_t k = 0; k < phi.size(); ++k) result.conversion[k] = -std::expm1(phi[k]);
    result.exposed = exposed;
    return result;
}

DlpColumnResult optimiseColumnDoses(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
                                    const DlpOptimiserOptions& options) {
    checkProblem(p);
    const double dMin = bondingDose(p.rateConstant, p.attenuation, p.gelPoint, p.layerThickness);
    if (p.maxDose < dMin) {
        std::ostringstream reason;
        reason << "DLP column: maximum dose " << p.maxDose * 100.0
               << " mJ/cm^2 is below the bonding dose d_min = " << dMin * 100.0
               << " mJ/cm^2 (Eq. 10), so no layer can be bonded";
        throw InputError(reason.str());
    }
    const std::vector<SolidRun> runs = solidRuns(solid);
    std::vector<size_t> skip(runs.size(), 0);
    auto patternFor = [&](const std::vector<size_t>& skips) {
        std::vector<uint8_t> exposed(solid.size(), 0);
        for (size_t r = 0; r < runs.size(); ++r)
            for (size_t k = runs[r].begin + skips[r]; k < runs[r].end; ++k) exposed[k] = 1;
        return exposed;
    };
    DlpColumnResult best = optimiseColumnDosesForPattern(solid, patternFor(skip), p, options);
    // Coordinate search over how many bottom layers of each run are left to print-through (a
    // pattern is feasible only if its first exposure can bond down to the run's bottom).
    for (int sweep = 0; sweep < options.maxSweeps; ++sweep) {
        bool improved = false;
        for (size_t r = 0; r < runs.size(); ++r) {
            std::vector<size_t> trial = skip;
            for (size_t s = 0; s < runs[r].end - runs[r].begin; ++s) {
                if (s == skip[r]) continue;
                trial[r] = s;
                std::vector<uint8_t> exposed = patternFor(trial);
                std::vector<double> lower, upper;
                if (!exposureBounds(exposed, solid, p, lower, upper))
                    break;  // larger skips need even more
                DlpColumnResult candidate =
                    optimiseColumnDosesForPattern(solid, exposed, p, options);
                if (candidate.objective < best.objective * (1.0 - 1e-12)) {
                    best = std::move(candidate);
                    skip[r] = s;
                    improved = true;
                }
            }
        }
        if (!improved) break;
    }
    return best;
}

}  // namespace vpsim::optimise
