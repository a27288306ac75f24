#include "vpsim/optimise/solvers/bounded_least_squares.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vpsim/core/error.h"

namespace vpsim::optimise {
namespace {

void checkInputs(const Transmission& t, const std::vector<double>& target,
                 const std::vector<double>& lower, const std::vector<double>& upper) {
    if (!(t.rateConstant > 0.0) || !(t.decay > 0.0 && t.decay < 1.0))
        throw InputError("bounded least squares: K must be > 0 and the decay in (0, 1)");
    if (target.size() != t.layers || lower.size() != t.layers || upper.size() != t.layers)
        throw InputError("bounded least squares: target and bounds must have one value per layer");
    for (size_t k = 0; k < t.layers; ++k)
        if (!(lower[k] <= upper[k]) || !std::isfinite(lower[k]) || !std::isfinite(upper[k]))
            throw InputError("bounded least squares: bounds of layer " + std::to_string(k) +
                             " are not finite with lower <= upper");
}

/// Minimises F over the free doses with the others held at x (see the header): fills y (free
/// entries solved, fixed ones copied) in O(n).
void solveFreeSubproblem(const Transmission& t, const std::vector<double>& target,
                         const std::vector<char>& free, const std::vector<double>& x,
                         std::vector<double>& y) {
    const double r = t.decay, k = t.rateConstant;
    y = x;
    double phiAbove = 0.0;  // phi_n = 0: nothing above the top layer
    long p = long(t.layers) - 1;
    while (p >= 0) {
        if (!free[p]) {
            phiAbove = r * phiAbove - k * x[p];
            --p;
            continue;
        }
        // Block: free layer f and the fixed layers below it down to the next free one.
        const long f = p;
        long q = f;
        while (q - 1 >= 0 && !free[q - 1]) --q;
        double s = 0.0, power = 1.0, num = 0.0, den = 0.0;
        for (long i = f; i >= q; --i) {
            if (i != f) s = r * s - k * x[i];
            num += power * (target[i] - s);
            den += power * power;
            power *= r;
        }
        const double theta = num / den;  // phi_f minimising the block's squares
        y[f] = (r * phiAbove - theta) / k;
        // phi at the block's bottom, for the layer below it
        s = 0.0;
        power = 1.0;
        for (long i = f - 1; i >= q; --i) {
            s = r * s - k * x[i];
            power *= r;
        }
        phiAbove = power * theta + s;
        p = q - 1;
    }
}

}  // namespace

std::vector<double> Transmission::apply(const std::vector<double>& dose) const {
    std::vector<double> phi(dose.size());
    double carried = 0.0;
    for (size_t i = dose.size(); i-- > 0;) {
        carried = dose[i] + decay * carried;  // accumulated print-through dose at layer i
        phi[i] = -rateConstant * carried;
    }
    return phi;
}

std::vector<double> Transmission::applyTransposed(const std::vector<double>& v) const {
    std::vector<double> out(v.size());
    double carried = 0.0;
    for (size_t i = 0; i < v.size(); ++i) {
        carried = v[i] + decay * carried;
        out[i] = -rateConstant * carried;
    }
    return out;
}

double Transmission::objective(const std::vector<double>& dose,
                               const std::vector<double>& target) const {
    std::vector<double> phi = apply(dose);
    double sum = 0.0;
    for (size_t i = 0; i < phi.size(); ++i) sum += (phi[i] - target[i]) * (phi[i] - target[i]);
    return sum;
}

BoundedLeastSquaresResult solveBoundedLeastSquares(const Transmission& t,
                                                   const std::vector<double>& target,
                                                   const std::vector<double>& lower,
                                                   const std::vector<double>& upper,
                                                   const std::vector<double>& start,
                                                   const BoundedLeastSquaresOptions& options) {
    checkInputs(t, target, lower, upper);
    const size_t n = t.layers;
    BoundedLeastSquaresResult result;
    std::vector<double>& x = result.dose;
    x = start.size() == n ? start : lower;
    std::vector<char> free(n, 0);
    for (size_t i = 0; i < n; ++i) {
        x[i] = std::clamp(x[i], lower[i], upper[i]);
        free[i] = x[i] > lower[i] && x[i] < upper[i];
    }
    double scale = 1.0;
    for (double v : t.applyTransposed(target)) scale = std::max(scale, 2.0 * std::abs(v));
    const double tol = options.tolerance * scale;
    const int maxIterations = options.iterationFactor * int(n) + 50;
    std::vector<double> y;
    for (int it = 0; it < maxIterations; ++it) {
        result.iterations = it;
        solveFreeSubproblem(t, target, free, x, y);
        // Step towards y until the first free dose meets a bound.
        double alpha = 1.0;
        long blocking = -1;
        for (size_t i = 0; i < n; ++i) {
            if (!free[i]) continue;
            double step = y[i] - x[i];
            if (y[i] < lower[i] && step < 0.0 && (lower[i] - x[i]) / step < alpha)
                alpha = (lower[i] - x[i]) / step, blocking = long(i);
            if (y[i] > upper[i] && step > 0.0 && (upper[i] - x[i]) / step < alpha)
                alpha = (upper[i] - x[i]) / step, blocking = long(i);
        }
        if (blocking >= 0) {
            for (size_t i = 0; i < n; ++i) {
                if (!free[i]) continue;
                const double moved = std::clamp(x[i] + alpha * (y[i] - x[i]), lower[i], upper[i]);
                const double width = upper[i] - lower[i];
                // Fix the blocking dose and any other that reached the bound it moves towards.
                bool toLower = y[i] < x[i] && moved - lower[i] <= 1e-15 * width;
                bool toUpper = y[i] > x[i] && upper[i] - moved <= 1e-15 * width;
                if (long(i) == blocking) (y[i] < lower[i] ? toLower : toUpper) = true;
                x[i] = toLower ? lower[i] : toUpper ? upper[i] : moved;
                if (toLower || toUpper) free[i] = 0;
            }
            continue;
        }
        x = y;
        // KKT: release the fixed dose whose multiplier has the wrong sign by the most.
        std::vector<double> residual = t.apply(x);
        for (size_t i = 0; i < n; ++i) residual[i] -= target[i];
        std::vector<double> g = t.applyTransposed(residual);
        long release = -1;
        double worst = tol;
        for (size_t i = 0; i < n; ++i) {
            if (free[i] || lower[i] == upper[i]) continue;
            double violation = (x[i] <= lower[i]) ? -2.0 * g[i] : 2.0 * g[i];
            if (violation > worst) worst = violation, release = long(i);
        }
        if (release < 0) {
            result.converged = true;
            break;
        }
        free[release] = 1;
    }
    result.objective = t.objective(x, target);
    return result;
}

BoundedLeastSquaresResult solveByProjectedGradient(const Transmission& t,
                                                   const std::vector<double>& target,
                                                   const std::vector<double>& lower,
                                                   const std::vector<double>& upper,
                                                   int maxIterations, double tolerance) {
    checkInputs(t, target, lower, upper);
    const double normBound = t.rateConstant / (1.0 - t.decay);
    const double step = 1.0 / (2.0 * normBound * normBound);
    BoundedLeastSquaresResult result;
    result.dose = lower;
    std::vector<double> residual(t.layers);
    for (int it = 0; it < maxIterations; ++it) {
        std::vector<double> phi = t.apply(result.dose);
        for (size_t k = 0; k < phi.size(); ++k) residual[k] = phi[k] - target[k];
        std::vector<double> g = t.applyTransposed(residual);
        double largestChange = 0.0, largestDose = 0.0;
        for (size_t k = 0; k < t.layers; ++k) {
            double before = result.dose[k];
            result.dose[k] = std::clamp(before - step * 2.0 * g[k], lower[k], upper[k]);  // Eq. 9
            largestChange = std::max(largestChange, std::abs(result.dose[k] - before));
            largestDose = std::max(largestDose, result.dose[k]);
        }
        result.iterations = it + 1;
        if (largestChange <= tolerance * std::max(largestDose, 1e-300)) {
            result.converged = true;
            break;
        }
    }
    result.objective = t.objective(result.dose, target);
    return result;
}

}  // namespace vpsim::optimise
