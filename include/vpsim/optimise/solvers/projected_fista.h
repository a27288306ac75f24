#pragma once
/// @file
/// FISTA with projection onto x >= 0 for a smooth convex f(A x) of non-negative variables (dot
/// energies), restarted whenever f rises (adaptive restart), returning the best iterate. The
/// laser inverse planner's two objectives use it: one layer's exposure against Etar and the
/// stack's shape objective. A is linear, so the image of the momentum point is combined from
/// the iterates' images: one forward and one gradient (adjoint) per iteration.
///
/// `Problem` provides
///     Image forward(const std::vector<double>& x) const;                    // A x
///     double value(const Image& ax) const;                                  // f(A x)
///     std::vector<double> gradient(const Image& ax) const;                  // A' f'(A x)
///     static void extrapolate(Image& out, const Image& a, const Image& b, double beta);
///                                                                           // a + beta (a - b)
/// and `step` holds one step length per variable (1 / L, or a diagonal majoriser's inverse).
/// `onIteration`, when given, is called as each iteration starts (progress reports).

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace vpsim::optimise {

struct FistaResult {
    std::vector<double> x;  ///< the best iterate (x >= 0)
    double best = 0;        ///< f at it
    int iterations = 0;     ///< iterations done
};

template <typename Problem>
FistaResult nonNegativeFista(const Problem& problem, std::vector<double> x,
                             const std::vector<double>& step, int iterations,
                             const std::function<void()>& onIteration = {}) {
    auto ax = problem.forward(x);
    double fx = problem.value(ax);
    FistaResult result{x, fx, 0};
    std::vector<double> y = x, xn(x.size());
    auto ay = ax;
    double t = 1;
    for (; result.iterations < iterations; ++result.iterations) {
        if (onIteration) onIteration();
        const std::vector<double> g = problem.gradient(ay);
        for (size_t k = 0; k < x.size(); ++k) xn[k] = std::max(y[k] - step[k] * g[k], 0.0);
        auto axn = problem.forward(xn);
        const double fn = problem.value(axn);
        if (fn > fx) {  // momentum overshot: restart from x with a plain projected step
            t = 1;
            y = x;
            ay = ax;
            continue;
        }
        if (fn < result.best) result.best = fn, result.x = xn;
        const double tn = 0.5 * (1 + std::sqrt(1 + 4 * t * t)), beta = (t - 1) / tn;
        for (size_t k = 0; k < x.size(); ++k) y[k] = xn[k] + beta * (xn[k] - x[k]);
        Problem::extrapolate(ay, axn, ax, beta);
        x.swap(xn);
        ax = std::move(axn);
        fx = fn;
        t = tn;
    }
    return result;
}

}  // namespace vpsim::optimise
