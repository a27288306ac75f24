#include <catch2/catch.hpp>

#include <random>

#include "vpsim/core/error.h"
#include "vpsim/optimise/solvers/qp_active_set.h"

using namespace vpsim;
using namespace vpsim::optimise;

namespace {

/// Brute force: every subset of the n bounds and m rows held at equality, each solved as an
/// equality-constrained least squares by its KKT system; the best feasible one is the optimum
/// (the QP is convex, so its minimiser is the minimiser over some active set).
double bruteForce(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::MatrixXd& C,
                  const Eigen::VectorXd& d, Eigen::VectorXd& best) {
    const int n = int(A.cols()), m = int(C.rows()), total = n + m;
    double bestValue = 1e300;
    for (int mask = 0; mask < (1 << total); ++mask) {
        std::vector<Eigen::VectorXd> rows;
        std::vector<double> rhs;
        for (int k = 0; k < total; ++k)
            if (mask & (1 << k)) {
                if (k < n) {
                    rows.push_back(Eigen::VectorXd::Unit(n, k));
                    rhs.push_back(0);
                } else {
                    rows.push_back(C.row(k - n).transpose());
                    rhs.push_back(d(k - n));
                }
            }
        const int e = int(rows.size());
        Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + e, n + e);
        Eigen::VectorXd r = Eigen::VectorXd::Zero(n + e);
        K.topLeftCorner(n, n) = A.transpose() * A;
        r.head(n) = A.transpose() * b;
        for (int k = 0; k < e; ++k) {
            K.block(n + k, 0, 1, n) = rows[k].transpose();
            K.block(0, n + k, n, 1) = rows[k];
            r(n + k) = rhs[k];
        }
        Eigen::FullPivLU<Eigen::MatrixXd> lu(K);
        if (lu.rank() < n + e) continue;  // dependent constraints: covered by a smaller subset
        Eigen::VectorXd x = lu.solve(r).head(n);
        if (x.minCoeff() < -1e-9 || (m > 0 && (C * x - d).maxCoeff() > 1e-9)) continue;
        double value = 0.5 * (A * x - b).squaredNorm();
        if (value < bestValue) bestValue = value, best = x;
    }
    return bestValue;
}

}  // namespace

// Tiny random problems (3-4 variables, 2-3 rows, exposure-like positive kernels and targets):
// the active-set optimum equals the brute-force optimum to 1e-9 (relative), both in value and
// in the minimiser (unique: A has full column rank).
TEST_CASE("the least-squares QP matches brute force on tiny problems", "[optimise][qp]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int withActiveRows = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const int n = 3 + trial % 2, rowsA = 5, m = 2 + trial % 2;
        Eigen::MatrixXd A(rowsA, n), C(m, n);
        Eigen::VectorXd b(rowsA), d(m);
        for (int i = 0; i < rowsA; ++i) {
            b(i) = 2 * u(rng) - 0.5;
            for (int j = 0; j < n; ++j) A(i, j) = u(rng);
        }
        for (int k = 0; k < m; ++k) {
            d(k) = 0.3 * u(rng);
            for (int j = 0; j < n; ++j) C(k, j) = u(rng);
        }
        LsqQpResult qp = solveLsqQp(A, b, C, d);
        Eigen::VectorXd xb;
        double brute = bruteForce(A, b, C, d, xb);
        INFO("trial " << trial);
        REQUIRE(qp.converged);
        CHECK(qp.objective == Approx(brute).epsilon(1e-9).margin(1e-12));
        CHECK((qp.x - xb).norm() < 1e-7);
        CHECK(qp.x.minCoeff() >= 0);
        CHECK((C * qp.x - d).maxCoeff() <= 1e-9);
        withActiveRows += qp.activeConstraints > 0;
    }
    CHECK(withActiveRows > 20);  // the general inequalities do bind in many trials
}

TEST_CASE("the least-squares QP without rows is non-negative least squares", "[optimise][qp]") {
    // min |x - b|^2, x >= 0: x = max(b, 0).
    Eigen::MatrixXd A = Eigen::MatrixXd::Identity(4, 4);
    Eigen::VectorXd b(4);
    b << 1.0, -2.0, 0.5, -0.1;
    LsqQpResult qp = solveLsqQp(A, b, Eigen::MatrixXd(0, 4), Eigen::VectorXd(0));
    CHECK(qp.converged);
    CHECK(qp.x(0) == Approx(1.0));
    CHECK(qp.x(1) == 0.0);
    CHECK(qp.x(2) == Approx(0.5));
    CHECK(qp.x(3) == 0.0);
    CHECK(qp.activeBounds == 2);
    // x = 0 already optimal (every bound stays active: an empty equality step) and no variables.
    LsqQpResult zero = solveLsqQp(A, -b.cwiseAbs(), Eigen::MatrixXd(0, 4), Eigen::VectorXd(0));
    CHECK(zero.converged);
    CHECK(zero.x.isZero(0.0));
    CHECK(zero.activeBounds == 4);
    LsqQpResult none =
        solveLsqQp(Eigen::MatrixXd(2, 0), b.head(2), Eigen::MatrixXd(0, 0), Eigen::VectorXd(0));
    CHECK(none.converged);
    CHECK(none.x.size() == 0);
    CHECK(none.objective == Approx(0.5 * b.head(2).squaredNorm()));
    Eigen::VectorXd bad(1);
    bad << -1.0;
    CHECK_THROWS_AS(solveLsqQp(A, b, Eigen::MatrixXd::Ones(1, 4), bad), InputError);
    CHECK_THROWS_AS(solveLsqQp(A, Eigen::VectorXd(3), Eigen::MatrixXd(0, 4), Eigen::VectorXd(0)),
                    InputError);
}
