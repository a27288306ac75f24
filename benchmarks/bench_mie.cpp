// Benchmark of the optics module. Prints JSON:
//  - time to compute the seed-000 slurry optics and phase table (Mie + 0.1-degree CDF + inverse);
//  - Mie evaluations (coefficients + efficiencies) per second at x = 10, 100, 1000, against a
//    plain Bohren & Huffman BHMIE-style implementation measured in the same run (complex upward
//    psi/xi recurrences, D_n from zero at a high start order);
//  - phase-intensity terms per second and the implied GFLOP/s against the machine's fp32 FMA
//    floor from docs/PLATFORM.md (177 GFLOP/s on 2 cores; this code is fp64, one thread).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpsim/optics/phase_table.h"
#include "vpsim/optics/slurry.h"

using namespace vpsim::optics;

namespace {

constexpr double MACHINE_FP32_FMA_GFLOPS = 177.0;  // docs/PLATFORM.md, 2 cores AVX2
constexpr double FLOPS_PER_PHASE_TERM = 14.0;      // per angle and term in miePhaseIntensity

template <typename F>
double medianSeconds(F&& work, int repeats) {
    std::vector<double> times;
    for (int r = 0; r < repeats; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        work();
        times.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
}

/// Baseline: BHMIE (Bohren & Huffman 1983, Appendix A) structure, m = n + ik convention.
/// Returns qext + qsca so the work cannot be optimised away.
double bhmieBaseline(std::complex<double> m, double x) {
    using C = std::complex<double>;
    const int nstop = static_cast<int>(x + 4.05 * std::cbrt(x) + 2.0);
    const C y = m * x;
    const int nmx = static_cast<int>(std::max(double(nstop), std::abs(y))) + 15;
    std::vector<C> d(static_cast<size_t>(nmx) + 1, C(0.0));
    for (int n = nmx; n > 1; --n) d[n - 1] = double(n) / y - 1.0 / (d[n] + double(n) / y);
    double psi0 = std::cos(x), psi1 = std::sin(x), chi0 = -std::sin(x), chi1 = std::cos(x);
    C xi1(psi1, -chi1);
    double qext = 0.0, qsca = 0.0;
    for (int n = 1; n <= nstop; ++n) {
        const double psi = (2.0 * n - 1.0) * psi1 / x - psi0;
        const double chi = (2.0 * n - 1.0) * chi1 / x - chi0;
        const C xi(psi, -chi);
        const C an =
            ((d[n] / m + double(n) / x) * psi - psi1) / ((d[n] / m + double(n) / x) * xi - xi1);
        const C bn =
            ((m * d[n] + double(n) / x) * psi - psi1) / ((m * d[n] + double(n) / x) * xi - xi1);
        qsca += (2.0 * n + 1.0) * (std::norm(an) + std::norm(bn));
        qext += (2.0 * n + 1.0) * (an.real() + bn.real());
        psi0 = psi1;
        psi1 = psi;
        chi0 = chi1;
        chi1 = chi;
        xi1 = C(psi1, -chi1);
    }
    return 2.0 / (x * x) * (qext + qsca);
}

}  // namespace

int main() {
    nlohmann::json out;
    out["benchmark"] = "mie";
    out["machine_floor_fp32_fma_gflops"] = MACHINE_FP32_FMA_GFLOPS;

    SlurrySpec seed;
    seed.wavelength = 405e-6;
    seed.resinIndex = 1.45;
    seed.resinPenetrationDepth = 0.119;
    seed.particleIndex = {1.75, 0.0};
    seed.radius = 2.5e-3;
    seed.volumeFraction = 0.5;
    SlurryOptics optics;
    const double seedSeconds = medianSeconds([&] { optics = computeSlurryOptics(seed); }, 9);
    out["seed000_phase_table"] = {
        {"seconds", seedSeconds},
        {"x", optics.x},
        {"panels", optics.phase.thetaEdges.size() - 1},
        {"table_size", optics.phase.inverseCdf.size()},
        {"g", optics.efficiencies.g},
        {"table_mean_cosine_error", optics.phase.tableMeanCosine() - optics.efficiencies.g}};

    nlohmann::json evaluations = nlohmann::json::array();
    double sink = 0.0;
    for (double x : {10.0, 100.0, 1000.0}) {
        const Complex m(1.5, -0.01);
        const int repeats = static_cast<int>(std::max(20.0, 2e6 / (x * x)));
        const double ours = medianSeconds(
                                [&] {
                                    for (int r = 0; r < repeats; ++r)
                                        sink += mieEfficiencies(mieCoefficients(m, x)).qext;
                                },
                                5) /
                            repeats;
        const double baseline = medianSeconds(
                                    [&] {
                                        for (int r = 0; r < repeats; ++r)
                                            sink += bhmieBaseline(std::conj(m), x);
                                    },
                                    5) /
                                repeats;
        const int terms = wiscombeTermCount(x);
        evaluations.push_back({{"x", x},
                               {"m", {m.real(), m.imag()}},
                               {"terms", terms},
                               {"evaluations_per_second", 1.0 / ours},
                               {"terms_per_second", terms / ours},
                               {"bhmie_baseline_evaluations_per_second", 1.0 / baseline},
                               {"speed_vs_baseline", baseline / ours}});
    }
    out["mie_evaluations"] = evaluations;

    // Angular sums, the cost of phase tables: K at every node of a 0.1-degree quadrature.
    nlohmann::json angular = nlohmann::json::array();
    for (double x : {56.24, 1000.0}) {
        MieCoefficients c = mieCoefficients({1.2069, 0.0}, x);
        ThetaQuadrature q = makeThetaQuadrature(phasePanelWidth(c.terms()));
        std::vector<double> k;
        const double seconds = medianSeconds([&] { k = phaseIntensityAtNodes(c, q); }, 5);
        sink += k[1];
        const double terms = double(q.nodeMu.size()) * c.terms();
        const double gflops = terms * FLOPS_PER_PHASE_TERM / seconds * 1e-9;
        angular.push_back({{"x", x},
                           {"angles", q.nodeMu.size()},
                           {"seconds", seconds},
                           {"angle_terms_per_second", terms / seconds},
                           {"gflops_fp64_one_thread", gflops},
                           {"fraction_of_machine_fp32_floor", gflops / MACHINE_FP32_FMA_GFLOPS}});
    }
    out["phase_intensity"] = angular;
    out["checksum"] = sink;
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
