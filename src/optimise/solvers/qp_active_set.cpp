#include "vpsim/optimise/solvers/qp_active_set.h"

#include <cmath>
#include <vector>

#include "vpsim/core/error.h"

namespace vpsim::optimise {
namespace {

/// Working set: bounds x_i = 0 (`fixed`) and general rows held at equality (`rows`).
struct WorkingSet {
    std::vector<char> fixed;
    std::vector<int> rows;
};

/// Equality-constrained step: minimise 1/2 p'Hp + g'p with p_i = 0 on fixed variables and
/// C_W p = 0. Returns the step p and the row multipliers mu (>= 0 at a KKT point).
void equalityStep(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, const Eigen::MatrixXd& C,
                  const WorkingSet& w, Eigen::VectorXd& p, Eigen::VectorXd& mu) {
    const int n = int(H.rows());
    std::vector<int> free;
    for (int i = 0; i < n; ++i)
        if (!w.fixed[i]) free.push_back(i);
    const int nf = int(free.size()), nr = int(w.rows.size());
    p = Eigen::VectorXd::Zero(n);
    mu = Eigen::VectorXd::Zero(nr);
    if (nf + nr == 0) return;  // every variable on its bound: no step (Eigen asserts on 0 x 0)
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nf + nr, nf + nr);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nf + nr);
    for (int a = 0; a < nf; ++a) {
        rhs(a) = -g(free[a]);
        for (int b = 0; b < nf; ++b) K(a, b) = H(free[a], free[b]);
        for (int r = 0; r < nr; ++r) K(a, nf + r) = K(nf + r, a) = C(w.rows[r], free[a]);
    }
    Eigen::VectorXd sol = K.fullPivLu().solve(rhs);
    for (int a = 0; a < nf; ++a) p(free[a]) = sol(a);
    mu = sol.tail(nr);
}

}  // namespace

LsqQpResult solveLsqQp(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::MatrixXd& C,
                       const Eigen::VectorXd& d, double ridge, int maxIterations) {
    const int n = int(A.cols()), m = int(C.rows());
    if (A.rows() != b.size() || (m > 0 && C.cols() != n) || d.size() != m || !(ridge >= 0))
        throw InputError("least-squares QP: mismatched matrix sizes or negative ridge");
    if (m > 0 && d.minCoeff() < 0)
        throw InputError("least-squares QP: a bound C x <= d with d < 0 makes x = 0 infeasible");
    const Eigen::MatrixXd H = A.transpose() * A + ridge * Eigen::MatrixXd::Identity(n, n);
    const Eigen::VectorXd Atb = A.transpose() * b;
    LsqQpResult result;
    if (n == 0) {  // nothing to solve (and Eigen asserts on reductions of empty matrices)
        result.converged = true;
        result.objective = 0.5 * b.squaredNorm();
        result.x = Eigen::VectorXd::Zero(0);
        return result;
    }
    const double scale = std::max(1.0, H.diagonal().cwiseAbs().maxCoeff());
    const double tol = 1e-12 * scale;
    if (maxIterations <= 0) maxIterations = 10 * (n + m) + 50;

    Eigen::VectorXd x = Eigen::VectorXd::Zero(n), p, mu;
    WorkingSet w{std::vector<char>(n, 1), {}};  // start: every bound active at x = 0
    Eigen::VectorXd slack = d;                  // d - C x
    for (int it = 0; it < maxIterations; ++it) {
        result.iterations = it + 1;
        Eigen::VectorXd g = H * x - Atb;
        equalityStep(H, g, C, w, p, mu);
        if (p.lpNorm<Eigen::Infinity>() <= 1e-12 * std::max(1.0, x.lpNorm<Eigen::Infinity>())) {
            // Multipliers: rows from the KKT solve, bounds nu_i = (g + C_W' mu)_i on fixed x_i.
            Eigen::VectorXd grad = g;
            for (size_t r = 0; r < w.rows.size(); ++r) grad += mu(r) * C.row(w.rows[r]).transpose();
            double most = -tol;
            int dropBound = -1, dropRow = -1;
            for (int i = 0; i < n; ++i)
                if (w.fixed[i] && grad(i) < most) most = grad(i), dropBound = i, dropRow = -1;
            for (size_t r = 0; r < w.rows.size(); ++r)
                if (mu(r) < most) most = mu(r), dropRow = int(r), dropBound = -1;
            if (dropBound < 0 && dropRow < 0) {
                result.converged = true;
                break;
            }
            if (dropBound >= 0)
                w.fixed[dropBound] = 0;
            else
                w.rows.erase(w.rows.begin() + dropRow);
            continue;
        }
        // Longest feasible step along p: bounds x_i + t p_i >= 0 and rows C x + t C p <= d.
        double t = 1.0;
        int blockBound = -1, blockRow = -1;
        for (int i = 0; i < n; ++i)
            if (!w.fixed[i] && p(i) < 0 && -x(i) / p(i) < t) t = -x(i) / p(i), blockBound = i;
        Eigen::VectorXd Cp = m > 0 ? Eigen::VectorXd(C * p) : Eigen::VectorXd();
        std::vector<char> inRows(m, 0);
        for (int r : w.rows) inRows[r] = 1;
        for (int r = 0; r < m; ++r)
            if (!inRows[r] && Cp(r) > 0 && std::max(slack(r), 0.0) / Cp(r) < t)
                t = std::max(slack(r), 0.0) / Cp(r), blockRow = r, blockBound = -1;
        x += t * p;
        if (m > 0) slack -= t * Cp;
        if (blockRow >= 0) {
            w.rows.push_back(blockRow);
        } else if (blockBound >= 0) {
            x(blockBound) = 0;
            w.fixed[blockBound] = 1;
        }
    }
    result.x = x.cwiseMax(0.0);
    Eigen::VectorXd r = A * result.x - b;
    result.objective = 0.5 * r.squaredNorm() + 0.5 * ridge * result.x.squaredNorm();
    for (int i = 0; i < n; ++i) result.activeBounds += result.x(i) == 0;
    if (m > 0) {
        Eigen::VectorXd s = d - C * result.x;
        for (int k = 0; k < m; ++k) result.activeConstraints += s(k) <= 1e-9 * (1 + std::abs(d(k)));
    }
    return result;
}

}  // namespace vpsim::optimise
