#include "vpsim/optimise/dlp/geometric_lp.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "glpk_programme.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"

namespace vpsim::optimise {

struct GeometricPatternLp::Impl {
    detail::Programme lp;
    std::vector<uint8_t> solid;
    DlpColumnProblem p;
    double ec = 0.0;
    std::vector<int> x;  // dose columns of the solid layers (0 elsewhere)
    std::vector<double> lo, hi;
};

GeometricPatternLp::GeometricPatternLp(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
                                       const DlpGeometricOptions& o)
    : mImpl(std::make_unique<Impl>()) {
    Impl& m = *mImpl;
    exposureBounds(std::vector<uint8_t>(solid.size(), 0), solid, p, m.lo, m.hi);  // checks p
    glp_term_out(GLP_OFF);
    m.solid = solid, m.p = p, m.ec = cure::fppGelDose(p.rateConstant, p.gelPoint);
    const size_t n = solid.size();
    const double r = std::exp(-p.attenuation * p.layerThickness);
    m.x.assign(n, 0);
    std::vector<int> d(n);
    for (size_t k = 0; k < n; ++k) {
        if (solid[k]) m.x[k] = m.lp.column(0.0, 0.0, 1e-4);  // tiny cost: less light on ties
        d[k] = m.lp.column(0.0, INFINITY, 0.0);
    }
    detail::addPrintThroughRows(m.lp, solid, r, m.x, d, o);
}

GeometricPatternLp::~GeometricPatternLp() = default;

double GeometricPatternLp::solve(const std::vector<uint8_t>& pattern, std::vector<double>& doses) {
    Impl& m = *mImpl;
    if (!exposureBounds(pattern, m.solid, m.p, m.lo, m.hi))
        return std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < m.solid.size(); ++k)
        if (m.solid[k]) {
            const double l = m.lo[k] / m.ec, h = m.hi[k] / m.ec;
            glp_set_col_bnds(m.lp.get(), m.x[k], l == h ? GLP_FX : GLP_DB, l, h);
        }
    glp_smcp sm;
    glp_init_smcp(&sm);
    sm.msg_lev = GLP_MSG_OFF;
    sm.meth = GLP_DUALP;  // only bounds change between patterns: the basis stays dual feasible
    ++mSolves;
    if (glp_simplex(m.lp.get(), &sm) != 0 || glp_get_status(m.lp.get()) != GLP_OPT)
        return std::numeric_limits<double>::infinity();
    doses.assign(m.solid.size(), 0.0);
    for (size_t k = 0; k < m.solid.size(); ++k)
        if (m.solid[k] && pattern[k]) doses[k] = glp_get_col_prim(m.lp.get(), m.x[k]) * m.ec;
    return glp_get_obj_val(m.lp.get());
}

std::vector<std::pair<size_t, size_t>> solidRuns(const std::vector<uint8_t>& solid) {
    std::vector<std::pair<size_t, size_t>> runs;
    for (size_t k = 0; k < solid.size(); ++k) {
        if (!solid[k]) continue;
        if (k == 0 || !solid[k - 1]) runs.push_back({k, k});
        runs.back().second = k;
    }
    return runs;
}

std::vector<uint8_t> periodicPattern(const std::vector<uint8_t>& solid, int gap, int skip) {
    if (gap < 1) throw InputError("DLP geometric: the periodic pattern's gap must be >= 1");
    std::vector<uint8_t> pattern(solid.size(), 0);
    for (const auto& [bottom, top] : solidRuns(solid)) {
        pattern[top] = 1;
        // Runs on the platform have no void below to keep dark: exposures go down to it.
        for (size_t k = bottom + (bottom == 0 ? 0 : size_t(std::max(skip, 0))); k < top;
             k += size_t(gap))
            pattern[k] = 1;
    }
    return pattern;
}

std::vector<uint8_t> greedyPattern(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
                                   int gap, const DlpGeometricOptions& o) {
    if (gap < 1) throw InputError("DLP geometric: the greedy pattern's gap must be >= 1");
    const double r = std::exp(-p.attenuation * p.layerThickness);
    const double cap = p.maxDose / cure::fppGelDose(p.rateConstant, p.gelPoint);
    const long window = longestGap(p);
    const bool runBottom = p.bonding == Bonding::RunBottom;
    const double c = 1.0 - o.margin;
    std::vector<uint8_t> pattern(solid.size(), 0);
    const auto runs = solidRuns(solid);
    double above = 0.0;  // D per Ec at the layer above the current exposure candidate
    long previous = long(solid.size());  // bottom of the run above
    for (size_t ri = runs.size(); ri-- > 0;) {
        const long b = long(runs[ri].first), t = long(runs[ri].second);
        above *= std::pow(r, double(previous - t - 1));  // through the void between the runs
        // e can be the lowest exposure if its largest dose cures the run down to its bottom
        // (under run-bottom bonding only within the longest gap of the bottom); its D then.
        auto lowest = [&](long e, double over) {
            if (e > b && (b == 0 || (runBottom && e - b + 1 > window) ||
                          std::pow(r, double(e - b)) * (cap + r * over) < 1.0))
                return -1.0;
            const double least = runBottom ? std::pow(r, -double(e - b + 1)) : 1.0 / r;
            return std::max(least + r * over, std::pow(r, -double(e - b)));
        };
        long q = t;
        double dq = lowest(t, above);
        pattern[size_t(t)] = 1;
        while (dq < 0.0) {
            // The layer within the gap below q that, as the lowest exposure, gives the smallest
            // peak dose plus void overshoot below the run; else the gap's end, exposed.
            const long end = std::max(b, q - gap);
            long e = end;
            double de = -1.0, score = INFINITY;
            for (long k = q - 1; k >= end; --k) {
                const double dTop = std::pow(r, -double(q - k)) + r * above;  // q's least D
                const double dk = lowest(k, std::pow(r, double(q - k - 1)) * dTop);
                if (dk < 0.0) continue;
                const double over = b > 0 ? std::pow(r, double(k - b + 1)) * dk - c : 0.0;
                const double value =
                    o.spreadWeight * std::max(dTop, dk) + o.violationWeight * std::max(0.0, over);
                if (value < score) score = value, e = k, de = dk;
            }
            e = std::max(e, end);
            above = std::pow(r, double(q - e - 1)) * (std::pow(r, -double(q - e)) + r * above);
            q = e, dq = de;
            pattern[size_t(q)] = 1;
        }
        above = std::pow(r, double(q - b)) * dq;  // D at the run's bottom
        previous = b;
    }
    return pattern;
}

int longestGap(const DlpColumnProblem& p) {
    const double ec = cure::fppGelDose(p.rateConstant, p.gelPoint);
    const double mule = p.attenuation * p.layerThickness;
    const int window = int(std::floor(std::log(p.maxDose / ec) / mule + 1e-12));
    if (window < 1) throw InputError("DLP geometric: d_max is below the bonding dose (Eq. 10)");
    return window;
}

int bottomSkip(const DlpColumnProblem& p, int gap) {
    const double mule = p.attenuation * p.layerThickness, r = std::exp(-mule);
    // Steady dose at an exposure of a gap-g periodic pattern with minimal doses, per Ec.
    const double rg = std::pow(r, gap), exposure = 1.0 / (rg * (1.0 - rg));
    int skip = int(std::floor(std::log(exposure) / mule + 1e-12));
    if (p.bonding == Bonding::RunBottom) skip = std::min(skip, longestGap(p) - 1);
    return std::max(skip, 0);
}

double structuralBound(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
                       const DlpGeometricOptions& o) {
    const double r = std::exp(-p.attenuation * p.layerThickness), c = 1.0 - o.margin;
    const double w = o.violationWeight, s = o.spreadWeight;
    const long window = longestGap(p);
    // Per run: B, the least violation-plus-spread cost, and V, the least violation cost. Runs'
    // violations add up and the spread is shared, so the objective is >= max_R B_R + sum of the
    // other runs' V.
    double violations = 0.0, excess = 0.0;
    for (const auto& [bottom, top] : solidRuns(solid)) {
        const long b = long(bottom), t = long(top);
        // No exposure at the run's top: its top node gets at most r (c + v) from the void above.
        double run = w * (1.0 - r * c), violation = run;
        for (long e = b; e <= t; ++e) {  // e: the run's lowest exposure
            const long j = e - b;
            double least = p.bonding == Bonding::RunBottom ? std::pow(r, -double(j + 1)) : 1.0 / r;
            // Exposures above e up to the top, each gap <= window, each bonding down (Eq. 10).
            const long above = (t - e + window - 1) / window;
            for (long i = 0; i < above; ++i) least += std::pow(r, double(i * window));
            const double rj = std::pow(r, double(j));
            auto gel = [&](double d) {  // gel shortfall at b, void b - 1 over the margin
                double v = w * std::max(0.0, 1.0 - rj * d);
                if (b > 0) v += w * std::max(0.0, r * rj * d - c);
                return v;
            };
            for (double d : {least, 1.0 / rj, c / (r * rj)}) {
                const double at = std::max(d, least);
                run = std::min(run, s * (1.0 - rj) * at + gel(at));  // spread >= D_e - D_b
                violation = std::min(violation, gel(at));
            }
        }
        violations += violation;
        excess = std::max(excess, run - violation);
    }
    return violations + excess;
}

}  // namespace vpsim::optimise
