// Control-variate estimates of the diffuse reflectance, the transmittance and the absorbed-within
// fractions from the terms shaders/include/photon_control.glsl tallies. Each term has mean zero,
// so y_b - beta . psi_b (y_b a batch's tally, psi_b its mean control terms per photon) has y's
// expectation for any fixed beta; the beta of least variance is the regression of y on psi.
// - The regression runs over the MC_CONTROL_BATCHES control batches, not the 64 batches: the ten
//   terms are strongly correlated, and fitted on 32 samples their coefficients scattered so much
//   that a refractive surface's gain (HG, n = 1.45) vanished.
// - Fitting beta on the photons it corrects would bias the estimate and its error slightly, so
//   the fit is cross-fitted: the even batches are corrected with the beta fitted on the odd
//   control batches and vice versa (a control batch has its batch's parity), which keeps the
//   estimate unbiased and the batch spread an honest standard error.

#include <cmath>

#include <Eigen/Dense>

#include "photon_params.h"
#include "vpsim/core/error.h"

namespace vpsim::transport {

namespace {

using BatchValues = std::array<double, MC_BATCHES>;

/// Least-squares beta of y_j = c + beta . psi_j over the non-empty control batches of one
/// parity (y_j and psi_j per photon). Terms that never vary (0 in a matched or semi-infinite
/// medium) or are collinear get 0; all are 0 when the half has too few batches for a fit.
Eigen::VectorXd fitBeta(const std::vector<double>& y, const Eigen::MatrixXd& psi,
                        const std::vector<uint64_t>& photons, int parity) {
    std::vector<int> used;
    for (int j = parity; j < MC_CONTROL_BATCHES; j += 2)
        if (photons[size_t(j)] > 0) used.push_back(j);
    Eigen::VectorXd beta = Eigen::VectorXd::Zero(MC_CONTROL_TERMS);
    const int n = int(used.size());
    if (n < 4 * MC_CONTROL_TERMS) return beta;
    // Columns scaled to unit spread, so that the rank threshold compares like with like.
    Eigen::VectorXd scale = Eigen::VectorXd::Zero(MC_CONTROL_TERMS);
    for (int c = 0; c < MC_CONTROL_TERMS; ++c) {
        double mean = 0, squares = 0;
        for (int j : used) mean += psi(j, c) / n;
        for (int j : used) squares += (psi(j, c) - mean) * (psi(j, c) - mean);
        scale[c] = squares > 0 ? std::sqrt(squares / n) : 0.0;
    }
    Eigen::MatrixXd x(n, MC_CONTROL_TERMS + 1);
    Eigen::VectorXd rhs(n);
    for (int i = 0; i < n; ++i) {
        const int j = used[size_t(i)];
        x(i, 0) = 1.0;
        for (int c = 0; c < MC_CONTROL_TERMS; ++c)
            x(i, c + 1) = scale[c] > 0 ? psi(j, c) / scale[c] : 0.0;
        rhs[i] = y[size_t(j)];
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
    qr.setThreshold(1e-9);
    const Eigen::VectorXd fit = qr.solve(rhs);
    for (int c = 0; c < MC_CONTROL_TERMS; ++c)
        if (scale[c] > 0 && std::isfinite(fit[c + 1])) beta[c] = fit[c + 1] / scale[c];
    return beta;
}

/// The batches of a tally (get reads it from a BatchTally or a ControlTally), corrected by their
/// cross-fitted controls when the run has them.
template <class Get>
BatchValues controlledBatches(const McResult& r, Get get) {
    BatchValues y{};
    for (int b = 0; b < MC_BATCHES; ++b) {
        const BatchTally& t = r.batches[size_t(b)];
        if (t.photons > 0) y[size_t(b)] = double(get(t)) / double(t.photons * r.launchWeight);
    }
    if (!r.controlled() || r.controlBatches.size() != size_t(MC_CONTROL_BATCHES)) return y;
    // Per photon: each control batch's tally and terms, and each batch's summed terms.
    std::vector<uint64_t> photons(MC_CONTROL_BATCHES);
    std::vector<double> yj(MC_CONTROL_BATCHES, 0.0);
    Eigen::MatrixXd psi = Eigen::MatrixXd::Zero(MC_CONTROL_BATCHES, MC_CONTROL_TERMS);
    Eigen::MatrixXd psiBatch = Eigen::MatrixXd::Zero(MC_BATCHES, MC_CONTROL_TERMS);
    const uint64_t total = r.total().photons;
    for (int j = 0; j < MC_CONTROL_BATCHES; ++j) {
        const ControlTally& c = r.controlBatches[size_t(j)];
        photons[size_t(j)] = photonsInBatch(r.setup.firstPhoton, total, j, MC_CONTROL_BATCHES);
        for (int t = 0; t < MC_CONTROL_TERMS; ++t)
            psiBatch(j % MC_BATCHES, t) += std::ldexp(double(c.controls[size_t(t)]), -32);
        if (photons[size_t(j)] == 0) continue;
        const double n = double(photons[size_t(j)]);
        yj[size_t(j)] = double(get(c)) / (n * r.launchWeight);
        for (int t = 0; t < MC_CONTROL_TERMS; ++t)
            psi(j, t) = std::ldexp(double(c.controls[size_t(t)]), -32) / n;
    }
    const Eigen::VectorXd beta[2] = {fitBeta(yj, psi, photons, 0), fitBeta(yj, psi, photons, 1)};
    BatchValues out = y;
    for (int b = 0; b < MC_BATCHES; ++b) {
        const uint64_t n = r.batches[size_t(b)].photons;
        if (n > 0) out[size_t(b)] -= psiBatch.row(b).dot(beta[(b + 1) % 2]) / double(n);
    }
    return out;
}

}  // namespace

bool McResult::controlled() const {
    return setup.controlVariates &&
           (setup.estimator == Estimator::Collision || setup.estimator == Estimator::Track);
}

std::array<double, MC_BATCHES> McResult::diffuseBatches() const {
    return controlledBatches(*this, [](const auto& t) { return t.diffuse; });
}

std::array<double, MC_BATCHES> McResult::transmittedBatches() const {
    return controlledBatches(*this, [](const auto& t) { return t.transmitted; });
}

std::array<double, MC_BATCHES> McResult::absorbedWithinBatches(size_t k) const {
    if (k >= 4)
        throw InputError("depth index " + std::to_string(k) + " out of range 0..3", "", "depths");
    return controlledBatches(*this, [k](const auto& t) { return t.absorbedWithin[k]; });
}

Fraction McResult::diffuse() const {
    return controlled() ? fractionOfBatches(*this, diffuseBatches()) : diffuseTally();
}

Fraction McResult::transmitted() const {
    return controlled() ? fractionOfBatches(*this, transmittedBatches()) : transmittedTally();
}

Fraction McResult::absorbedWithin(size_t k) const {
    return controlled() ? fractionOfBatches(*this, absorbedWithinBatches(k))
                        : absorbedWithinTally(k);
}

Fraction McResult::absorbed() const {
    if (!controlled()) return absorbedTally();
    const BatchValues rd = diffuseBatches(), tt = transmittedBatches();
    BatchValues a{};
    for (int b = 0; b < MC_BATCHES; ++b) {
        const BatchTally& t = batches[size_t(b)];
        if (t.photons == 0) continue;
        const double launched = double(t.photons * launchWeight);
        a[size_t(b)] =
            1.0 - double(t.specular + t.escaped) / launched - rd[size_t(b)] - tt[size_t(b)];
    }
    return fractionOfBatches(*this, a);
}

}  // namespace vpsim::transport
