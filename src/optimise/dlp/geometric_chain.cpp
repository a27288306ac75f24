#include "vpsim/optimise/dlp/geometric_chain.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "glpk_programme.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"

namespace vpsim::optimise {

GeometricChainLp::GeometricChainLp(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
                                   const DlpGeometricOptions& o)
    : mSolid(solid), mP(p), mO(o) {
    exposureBounds(std::vector<uint8_t>(solid.size(), 0), solid, p, mLo, mHi);  // checks p
    mEc = cure::fppGelDose(p.rateConstant, p.gelPoint);
    mR = std::exp(-p.attenuation * p.layerThickness);
}

bool GeometricChainLp::chain(const std::vector<uint8_t>& pattern) {
    if (!exposureBounds(pattern, mSolid, mP, mLo, mHi)) return false;
    const long n = long(mSolid.size());
    mE.clear();
    for (long k = n - 1; k >= 0; --k)
        if (pattern[size_t(k)]) mE.push_back(k);
    const size_t m = mE.size();
    mDarkViolation = 0.0;  // solid nodes above the top exposure get no light: 1 each
    for (long k = m ? mE[0] + 1 : 0; k < n; ++k)
        if (mSolid[size_t(k)]) mDarkViolation += mO.violationWeight;
    mRho.assign(m, 0.0), mDeep.assign(m, 0), mVoid.assign(m, -1);
    for (size_t i = 0; i < m; ++i) {
        if (i > 0) mRho[i] = std::pow(mR, double(mE[i - 1] - mE[i]));
        const long end = i + 1 < m ? mE[i + 1] : -1;
        for (long k = mE[i]; k > end; --k) {
            if (mSolid[size_t(k)]) mDeep[i] = int(mE[i] - k);
            if (!mSolid[size_t(k)] && mVoid[i] < 0) mVoid[i] = int(mE[i] - k);
        }
    }
    return true;
}

double GeometricChainLp::solve(const std::vector<uint8_t>& pattern, std::vector<double>& doses) {
    if (!chain(pattern)) return std::numeric_limits<double>::infinity();
    ++mSolves;
    const double value = band(doses);
    if (value >= 0.0) return value;
    --mSolves;
    return solveLp(pattern, doses);
}

double GeometricChainLp::band(std::vector<double>& doses) {
    const size_t m = mE.size();
    if (m == 0 || mDarkViolation > 0.0) return -1.0;
    const double c = 1.0 - mO.margin;
    std::vector<double> deep(m), upper(m), l(m);
    for (size_t i = 0; i < m; ++i) {
        deep[i] = std::pow(mR, -double(mDeep[i]));
        upper[i] = mVoid[i] >= 0 ? c * std::pow(mR, -double(mVoid[i])) : INFINITY;
    }
    upper[0] = std::min(upper[0], mHi[size_t(mE[0])] / mEc);
    // Least solution of D_i >= L r^{-M_i} and the dose boxes; feasible: under the upper bounds.
    auto least = [&](double band) {
        for (size_t i = 0; i < m; ++i) {
            const double lo = mLo[size_t(mE[i])] / mEc;
            l[i] = std::max(band * deep[i], i ? mRho[i] * l[i - 1] + lo : lo);
        }
        for (size_t i = m; i-- > 1;)
            l[i - 1] = std::max(l[i - 1], (l[i] - mHi[size_t(mE[i])] / mEc) / mRho[i]);
        bool feasible = true;
        double high = 0.0;
        for (size_t i = 0; i < m; ++i) {
            feasible = feasible && l[i] <= upper[i] * (1 + 1e-12);
            high = std::max(high, l[i]);
        }
        return std::make_pair(feasible, high - band);  // psi(L) = max l(L) - L
    };
    if (!least(1.0).first) return -1.0;
    // Certificate that no violation pays: any D with min D = L < 1 costs at least
    // S psi(L) + W (1 - L), convex in L; its slope just below 1 must not be negative.
    const double eta = 1e-7;
    const double slope = (least(1.0).second - least(1.0 - eta).second) / eta;
    if (mO.spreadWeight * slope < -mO.violationWeight * (1 - 1e-9)) return -1.0;
    double top = 1.0, step = 1.0;  // the largest feasible band: doubling, then bisection
    while (step < 1e6 && least(1.0 + step).first) top = 1.0 + step, step *= 2.0;
    double a = top, b = 1.0 + step;
    for (int it = 0; it < 60 && b - a > 1e-13 * b; ++it) {
        const double mid = 0.5 * (a + b);
        (least(mid).first ? a : b) = mid;
    }
    top = a;
    // Golden section on the convex psi over [1, top].
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double lo = 1.0, hi = top, x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = least(x1).second, f2 = least(x2).second;
    for (int it = 0; it < 80 && hi - lo > 1e-12 * hi; ++it) {
        if (f1 <= f2)
            hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = least(x1).second;
        else
            lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = least(x2).second;
    }
    double best = 1.0, bestValue = least(1.0).second;
    for (double x : {lo, hi, 0.5 * (lo + hi), top})
        if (double v = least(x).second; v < bestValue) best = x, bestValue = v;
    least(best);
    double high = 0.0, low = INFINITY, light = 0.0;
    doses.assign(mSolid.size(), 0.0);
    for (size_t i = 0; i < m; ++i) {
        const size_t k = size_t(mE[i]);
        const double x = l[i] - (i ? mRho[i] * l[i - 1] : 0.0);
        doses[k] = std::clamp(x * mEc, mLo[k], mHi[k]);
        light += doses[k] / mEc;
        high = std::max(high, l[i]), low = std::min(low, l[i] / deep[i]);
    }
    return mO.spreadWeight * (high - low) + 1e-4 * light;
}

double GeometricChainLp::solveLp(const std::vector<uint8_t>& pattern, std::vector<double>& doses) {
    if (!chain(pattern)) return std::numeric_limits<double>::infinity();
    ++mSolves, ++mLpSolves;
    const double w = mO.violationWeight, s = mO.spreadWeight, c = 1.0 - mO.margin;
    const size_t m = mE.size();
    doses.assign(mSolid.size(), 0.0);
    if (m == 0) return mDarkViolation;
    // Nodes per segment, shallowest first: depth j below the exposure (D = r^j D_i), solid?
    std::vector<std::vector<std::pair<int, bool>>> nodes(m);
    for (size_t i = 0; i < m; ++i) {
        const long end = i + 1 < m ? mE[i + 1] : -1;
        for (long k = mE[i]; k > end; --k)
            nodes[i].push_back({int(mE[i] - k), bool(mSolid[size_t(k)])});
    }
    detail::Programme lp;
    std::vector<int> d(m);
    for (size_t i = 0; i < m; ++i) {
        const double light = 1e-4 * (1.0 - (i + 1 < m ? mRho[i + 1] : 0.0));  // sum of x_i
        const size_t k = size_t(mE[i]);
        d[i] =
            i == 0 ? lp.column(mLo[k] / mEc, mHi[k] / mEc, light) : lp.column(0.0, INFINITY, light);
    }
    const int up = lp.column(0.0, INFINITY, s);
    const int low = lp.column(0.0, mDarkViolation > 0.0 ? 0.0 : INFINITY, -s);
    for (size_t i = 0; i < m; ++i) {
        if (i > 0) {
            const double l = mLo[size_t(mE[i])] / mEc, h = mHi[size_t(mE[i])] / mEc;
            lp.row({{d[i], 1.0}, {d[i - 1], -mRho[i]}}, l == h ? GLP_FX : GLP_DB, l, h);
        }
        lp.row({{d[i], 1.0}, {up, -1.0}}, GLP_UP, 0.0, 0.0);
        lp.row({{d[i], std::pow(mR, mDeep[i])}, {low, -1.0}}, GLP_LO, 0.0, 0.0);
    }
    // Gel rows: the deepest solid and shallowest void node of each segment, then the violated.
    std::vector<std::vector<uint8_t>> inLp(m);
    auto addRow = [&](size_t i, size_t q) {
        const auto [depth, solid] = nodes[i][q];
        const int slack = lp.column(0.0, INFINITY, w);
        const double f = std::pow(mR, depth);
        if (solid)
            lp.row({{d[i], f}, {slack, 1.0}}, GLP_LO, 1.0, 0.0);
        else
            lp.row({{d[i], f}, {slack, -1.0}}, GLP_UP, 0.0, c);
        inLp[i][q] = 1;
    };
    for (size_t i = 0; i < m; ++i) {
        inLp[i].assign(nodes[i].size(), 0);
        addRow(i,
               size_t(std::find(nodes[i].begin(), nodes[i].end(), std::make_pair(mDeep[i], true)) -
                      nodes[i].begin()));
        if (mVoid[i] >= 0) addRow(i, size_t(mVoid[i]));
    }
    glp_smcp sm;
    glp_init_smcp(&sm);
    sm.msg_lev = GLP_MSG_OFF;
    std::vector<double> value(m);
    sm.meth = GLP_DUALP;  // from the slack basis: dual feasible but for the band's bottom
    for (;;) {
        if (glp_simplex(lp.get(), &sm) != 0 || glp_get_status(lp.get()) != GLP_OPT)
            throw InputError("DLP geometric: GLPK failed on a pattern's chain LP");
        for (size_t i = 0; i < m; ++i) value[i] = glp_get_col_prim(lp.get(), d[i]);
        bool added = false;
        for (size_t i = 0; i < m; ++i)
            for (size_t q = 0; q < nodes[i].size(); ++q) {
                const double dk = std::pow(mR, nodes[i][q].first) * value[i];
                const bool violated = nodes[i][q].second ? dk < 1.0 - 1e-12 : dk > c + 1e-12;
                if (violated && !inLp[i][q]) addRow(i, q), added = true;
            }
        if (!added) break;
        sm.meth = GLP_DUALP;  // added rows keep the basis dual feasible
    }
    for (size_t i = 0; i < m; ++i) {
        const size_t k = size_t(mE[i]);
        doses[k] =
            std::clamp((value[i] - (i > 0 ? mRho[i] * value[i - 1] : 0.0)) * mEc, mLo[k], mHi[k]);
    }
    return glp_get_obj_val(lp.get()) + mDarkViolation;
}

}  // namespace vpsim::optimise
