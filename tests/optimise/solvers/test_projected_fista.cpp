// The shared projected FISTA (optimise/solvers/projected_fista.h) on small non-negative least
// squares problems against brute force over every active set.
#include <catch2/catch.hpp>

#include <random>

#include <Eigen/Dense>

#include "vpsim/optimise/solvers/projected_fista.h"

using namespace vpsim::optimise;

namespace {

/// f(x) = 1/2 |A x - b|^2 with the image A x as an Eigen vector.
struct LeastSquares {
    Eigen::MatrixXd A;
    Eigen::VectorXd b;
    Eigen::VectorXd forward(const std::vector<double>& x) const {
        return A * Eigen::Map<const Eigen::VectorXd>(x.data(), long(x.size()));
    }
    double value(const Eigen::VectorXd& ax) const { return 0.5 * (ax - b).squaredNorm(); }
    std::vector<double> gradient(const Eigen::VectorXd& ax) const {
        const Eigen::VectorXd g = A.transpose() * (ax - b);
        return {g.data(), g.data() + g.size()};
    }
    static void extrapolate(Eigen::VectorXd& out, const Eigen::VectorXd& a,
                            const Eigen::VectorXd& b, double beta) {
        out = a + beta * (a - b);
    }
};

/// Brute force: the unconstrained least squares on every subset of free variables (the others
/// at 0); the best one with its free variables non-negative is the optimum (the problem is
/// convex, so its minimiser is the minimiser on some face).
double bruteForce(const LeastSquares& p) {
    const int n = int(p.A.cols());
    double best = 1e300;
    for (int mask = 0; mask < (1 << n); ++mask) {
        std::vector<int> free;
        for (int k = 0; k < n; ++k)
            if (mask & (1 << k)) free.push_back(k);
        Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
        if (!free.empty()) {
            Eigen::MatrixXd Af(p.A.rows(), long(free.size()));
            for (size_t k = 0; k < free.size(); ++k) Af.col(long(k)) = p.A.col(free[k]);
            const Eigen::VectorXd xf = Af.colPivHouseholderQr().solve(p.b);
            if (xf.minCoeff() < 0) continue;
            for (size_t k = 0; k < free.size(); ++k) x(free[k]) = xf(long(k));
        }
        best = std::min(best, p.value(p.A * x));
    }
    return best;
}

}  // namespace

TEST_CASE("projected FISTA reaches the non-negative least-squares optimum", "[optimise]") {
    std::mt19937 rng(7);
    std::normal_distribution<double> normal;
    for (int trial = 0; trial < 20; ++trial) {
        LeastSquares p{Eigen::MatrixXd(8, 5), Eigen::VectorXd(8)};
        for (long i = 0; i < 8; ++i) {
            p.b(i) = normal(rng);
            for (long j = 0; j < 5; ++j) p.A(i, j) = normal(rng);
        }
        const double lipschitz =
            Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p.A.transpose() * p.A)
                .eigenvalues()
                .maxCoeff();
        const std::vector<double> step(5, 1.0 / lipschitz);
        const FistaResult r = nonNegativeFista(p, std::vector<double>(5, 1.0), step, 3000);
        const double exact = bruteForce(p);
        INFO("trial " << trial << ": FISTA " << r.best << ", brute force " << exact);
        CHECK(r.best == Approx(exact).epsilon(1e-6).margin(1e-9));
        for (double x : r.x) CHECK(x >= 0);
        CHECK(r.best == Approx(p.value(p.forward(r.x))));  // the value of the returned iterate
        CHECK(r.iterations == 3000);
    }
}
