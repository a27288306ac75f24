#pragma once
/// @file
/// A small dense least-squares quadratic programme solved exactly by a primal active-set method
/// (Nocedal & Wright, Numerical Optimization, Alg. 16.3):
///
///     minimise 1/2 |A x - b|^2   subject to   x >= 0,   C x <= d,
///
/// the form of seed 000 Eq. 17 and 19 (dot exposure times T >= 0, exposures K T below the lifted
/// bounds E_c + a_i Etar). The start x = 0 is feasible when d >= 0 (true for lifted bounds), so
/// every iterate is feasible; each iteration solves the equality-constrained sub-problem on the
/// working set by a dense KKT system (Eigen, complete-pivoting LU for degenerate working sets) and
/// either takes the longest feasible step or drops the constraint with the most negative
/// multiplier. Sizes up to a few hundred variables and a few thousand constraints.

#include <Eigen/Dense>

namespace vpsim::optimise {

struct LsqQpResult {
    Eigen::VectorXd x;     ///< the minimiser
    double objective = 0;  ///< 1/2 |A x - b|^2
    int iterations = 0;
    int activeBounds = 0;       ///< x_i = 0 at the solution
    int activeConstraints = 0;  ///< rows of C x <= d that hold with equality
    bool converged = false;     ///< KKT conditions met within the iteration limit
};

/// Solves the problem above. `ridge` (>= 0) adds ridge/2 |x|^2 so a rank-deficient A still has a
/// unique minimiser. C may have zero rows.
/// @throw InputError for mismatched sizes or d with a negative entry (x = 0 infeasible)
LsqQpResult solveLsqQp(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::MatrixXd& C,
                       const Eigen::VectorXd& d, double ridge = 0.0, int maxIterations = 0);

}  // namespace vpsim::optimise
