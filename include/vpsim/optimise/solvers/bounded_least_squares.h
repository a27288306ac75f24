#pragma once
/// @file
/// Exact bounded least squares for a print-through column (seed 001 Eq. 7-8 with box bounds):
///     minimise F(d) = ||T d - t||^2  subject to  lower <= d <= upper,
/// where T is the column's transmission matrix, T_pr = -K r^(r-p) for r >= p (r = exp(-mu Le)).
///
/// Why a dedicated solver: T^-1 is bidiagonal (d_p = (r phi_{p+1} - phi_p) / K with phi = T d),
/// so with some doses held at their bounds the remaining free doses reparametrise phi into
/// independent blocks: phi at a free layer f is free, and the fixed layers below it (down to the
/// next free layer) follow from it by phi_p = r phi_{p+1} - K d_p. Each block's least squares is
/// one scalar closed form, so the free-set subproblem costs O(n) with no factorisation. A primal
/// active-set method (Lawson-Hanson style: release the most violated multiplier, step to the
/// first blocking bound) on top of it is exact (finite termination on this strictly convex
/// problem) at O(n) per active-set change.
/// Units: dose mJ/mm^2, K mm^2/mJ.

#include <cstddef>
#include <vector>

namespace vpsim::optimise {

/// The column's transmission operator T (Eq. 7): n layers, K, and r = exp(-mu Le).
struct Transmission {
    size_t layers = 0;
    double rateConstant = 0.0;  ///< K, mm^2/mJ (> 0)
    double decay = 0.0;         ///< r = exp(-mu Le) in (0, 1)

    /// phi = T d in O(n).
    std::vector<double> apply(const std::vector<double>& dose) const;
    /// T^T v in O(n).
    std::vector<double> applyTransposed(const std::vector<double>& v) const;
    /// ||T d - t||^2.
    double objective(const std::vector<double>& dose, const std::vector<double>& target) const;
};

/// Outcome of a bounded least-squares solve.
struct BoundedLeastSquaresResult {
    std::vector<double> dose;  ///< the minimiser, within the bounds
    double objective = 0.0;    ///< F at the minimiser
    int iterations = 0;        ///< active-set changes
    bool converged = false;    ///< KKT conditions met to the tolerance
};

/// Options of the active-set solve.
struct BoundedLeastSquaresOptions {
    /// KKT tolerance on multipliers, relative to max(1, ||T^T t||_inf).
    double tolerance = 1e-11;
    /// Active-set changes allowed, as a multiple of n (plus 50).
    int iterationFactor = 20;
};

/// Solves min ||T d - t||^2 on lower <= d <= upper exactly (active set; see file comment).
/// `start`, if non-empty, is a warm start (clamped into the bounds).
/// @throw InputError on mismatched lengths, lower > upper or a bad operator
BoundedLeastSquaresResult solveBoundedLeastSquares(const Transmission& t,
                                                   const std::vector<double>& target,
                                                   const std::vector<double>& lower,
                                                   const std::vector<double>& upper,
                                                   const std::vector<double>& start = {},
                                                   const BoundedLeastSquaresOptions& options = {});

/// Reference solver: Eq. 9's projected gradient descent (step 1 / (2 ||T||^2) with the bound
/// ||T||_2 <= K / (1 - r)) from `start` (or lower). Slow (linear rate ~ 1 - 1/cond(T^T T)); kept
/// as the independent check of solveBoundedLeastSquares.
/// @throw InputError as solveBoundedLeastSquares
BoundedLeastSquaresResult solveByProjectedGradient(
    const Transmission& t, const std::vector<double>& target, const std::vector<double>& lower,
    const std::vector<double>& upper, int maxIterations = 200000, double tolerance = 1e-13);

}  // namespace vpsim::optimise
