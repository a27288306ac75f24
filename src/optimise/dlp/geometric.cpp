#include "vpsim/optimise/dlp/geometric.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <unordered_set>

#include "glpk_programme.h"
#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"
#include "vpsim/optimise/dlp/geometric_chain.h"
#include "vpsim/optimise/dlp/geometric_lp.h"
#include "vpsim/optimise/dlp/pattern_search.h"

namespace vpsim::optimise {
namespace {

using detail::Programme;

/// The column's mixed-integer programme (file comment of geometric.h).
struct GeometricModel {
    Programme lp;
    std::vector<int> x, z;
    double ec = 0.0, r = 0.0;
    size_t n = 0;
    std::vector<uint8_t> solid;
};

/// Builds the programme. @throw InputError on bad parameters
std::unique_ptr<GeometricModel> buildModel(const std::vector<uint8_t>& solid,
                                           const DlpColumnProblem& p,
                                           const DlpGeometricOptions& o) {
    auto model = std::make_unique<GeometricModel>();
    Programme& lp = model->lp;
    std::vector<double> lo, hi;
    exposureBounds(std::vector<uint8_t>(solid.size(), 0), solid, p, lo, hi);  // checks p
    if (!(o.margin >= 0.0 && o.margin < 1.0))
        throw InputError("DLP geometric: margin must lie in [0, 1)");
    const double ec = cure::fppGelDose(p.rateConstant, p.gelPoint);
    const double mule = p.attenuation * p.layerThickness, r = std::exp(-mule);
    const double cap = p.maxDose / ec;  // d_max in units of Ec
    const int window = longestGap(p);   // longest allowed n_z
    const size_t n = solid.size();
    glp_term_out(GLP_OFF);
    std::vector<int> x(n, 0), z(n, 0), y(n, 0), d(n);
    for (size_t k = 0; k < n; ++k) {
        if (solid[k]) {
            x[k] = lp.column(0.0, cap, 1e-4);  // tiny dose cost breaks ties towards less light
            z[k] = lp.column(0.0, 1.0, 0.0, true);
            y[k] = lp.column(0.0, 1.0, 0.0);  // some exposure at or below k in this run
        }
        d[k] = lp.column(0.0, INFINITY, 0.0);
    }
    detail::addPrintThroughRows(lp, solid, r, x, d, o);
    const bool runBottom = p.bonding == Bonding::RunBottom;
    for (size_t q = 0; q < n; ++q) {
        if (!solid[q]) continue;
        size_t begin = q;
        while (begin > 0 && solid[begin - 1]) --begin;
        lp.row({{x[q], 1.0}, {z[q], -cap}}, GLP_UP, 0.0, 0.0);             // x <= d_max z
        lp.row({{x[q], 1.0}, {z[q], -std::exp(mule)}}, GLP_LO, 0.0, 0.0);  // n_z >= 1
        // Monotone indicator: y_q = y_{q-1} or z_q (the surface counts under run-bottom).
        const bool below = q > begin;
        lp.row({{y[q], 1.0}, {z[q], -1.0}}, GLP_LO, 0.0, 0.0);
        if (below) {
            lp.row({{y[q], 1.0}, {y[q - 1], -1.0}}, GLP_LO, 0.0, 0.0);
            lp.row({{y[q], 1.0}, {y[q - 1], -1.0}, {z[q], -1.0}}, GLP_UP, 0.0, 0.0);
        } else {
            lp.row({{y[q], 1.0}, {z[q], -1.0}}, GLP_UP, 0.0, runBottom ? 1.0 : 0.0);
            if (runBottom) lp.row({{y[q], 1.0}}, GLP_LO, 1.0, 0.0);
        }
        // Eq. 10 for each gap k the cap allows: the previous exposure (or surface) at q - k.
        for (int k = 2; k <= window; ++k) {
            const long prev = long(q) - k;
            const bool surface = prev == long(begin) - 1;
            if (prev < long(begin) - 1 || (surface && !runBottom)) break;
            const double lambda = std::exp(mule * k);
            std::vector<std::pair<int, double>> t{{x[q], 1.0}, {z[q], -lambda}};
            for (long j = prev + 1; j < long(q); ++j) t.push_back({z[j], lambda});
            if (!surface) t.push_back({z[prev], -lambda});
            lp.row(t, GLP_LO, surface ? 0.0 : -lambda, 0.0);
        }
        // No gap longer than the window between two exposures (or above the surface).
        const long past = long(q) - window - 1;
        if (past >= long(begin) - 1 && (past >= long(begin) || runBottom)) {
            std::vector<std::pair<int, double>> t{{z[q], 1.0}};
            for (long j = past + 1; j < long(q); ++j) t.push_back({z[j], -1.0});
            if (past >= long(begin)) {
                t.push_back({y[past], 1.0});
                lp.row(t, GLP_UP, 0.0, 1.0);
            } else {
                lp.row(t, GLP_UP, 0.0, 0.0);  // the surface is "exposed" under run-bottom
            }
        }
    }
    model->x = x, model->z = z, model->ec = ec, model->r = r, model->n = n, model->solid = solid;
    return model;
}

/// The MILP's LP relaxation (z in [0, 1]): a lower bound on every pattern's objective.
double relaxationBound(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
                       const DlpGeometricOptions& o) {
    std::unique_ptr<GeometricModel> model = buildModel(solid, p, o);
    for (size_t k = 0; k < solid.size(); ++k)
        if (solid[k]) glp_set_col_bnds(model->lp.get(), model->z[k], GLP_DB, 0.0, 1.0);
    glp_smcp sm;
    glp_init_smcp(&sm);
    sm.msg_lev = GLP_MSG_OFF;
    if (glp_simplex(model->lp.get(), &sm) == 0 && glp_get_status(model->lp.get()) == GLP_OPT)
        return std::max(0.0, glp_get_obj_val(model->lp.get()));
    return 0.0;
}

/// The result of doses `dose` with objective `best` and lower bound `bound`.
DlpGeometricResult finish(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
                          const DlpGeometricOptions& o, const std::vector<double>& dose,
                          double best, double bound) {
    DlpGeometricResult out;
    const size_t n = solid.size();
    const double ec = cure::fppGelDose(p.rateConstant, p.gelPoint);
    const double r = std::exp(-p.attenuation * p.layerThickness);
    out.dose = dose;
    out.accumulated.assign(n, 0.0);
    out.objective = best;
    out.lowerBound = bound;
    out.gap = (best - out.lowerBound) / std::max(std::abs(best), 1e-12);
    out.optimal = out.gap <= 1e-9;
    // Recompute D from the doses (not GLPK's values) so the result is self-consistent.
    double carried = 0.0;
    for (size_t k = n; k-- > 0;) out.accumulated[k] = carried = out.dose[k] + r * carried;
    double high = 0.0, low = INFINITY;
    for (size_t k = 0; k < n; ++k) {
        const double v = out.accumulated[k] / ec;
        if (solid[k]) {
            out.violation += std::max(0.0, 1.0 - v);
            high = std::max(high, v), low = std::min(low, v);
        } else {
            out.violation += std::max(0.0, v - (1.0 - o.margin));
        }
    }
    out.spread = high >= low ? high - low : 0.0;
    return out;
}

}  // namespace

namespace {

/// The search's incumbent, and the patterns already solved (skipped: +inf, since the search only
/// takes strict improvements; start patterns often coincide, switches often undo an earlier one).
struct Incumbent {
    GeometricChainLp& lp;
    std::vector<uint8_t> pattern;
    std::vector<double> dose;
    double value = INFINITY;
    std::unordered_set<std::string> seen;

    /// Solves `trial` if new; takes it when it beats the incumbent by more than `tolerance`.
    bool consider(const std::vector<uint8_t>& trial, double tolerance = 0.0) {
        if (!seen.emplace(trial.begin(), trial.end()).second) return false;
        std::vector<double> doses;
        const double v = lp.solve(trial, doses);
        if (!(v < value - tolerance)) return false;
        value = v, pattern = trial, dose = std::move(doses);
        return true;
    }
};

/// Switches single layers within options.searchDepth of each run's bottom (and, with moves 3,
/// moves an exposure by one layer): only those layers decide where a down-facing surface ends.
void improveLocally(const std::vector<uint8_t>& solid, const DlpGeometricOptions& o,
                    Incumbent& inc) {
    const size_t n = solid.size();
    std::vector<uint8_t> movable(n, 0);
    for (const auto& [bottom, top] : solidRuns(solid))
        for (size_t k = bottom; k <= top && k - bottom < size_t(o.searchDepth); ++k) movable[k] = 1;
    for (int pass = 0; pass < o.maxPasses; ++pass) {
        bool improved = false;
        for (size_t k = 0; k < n; ++k) {
            if (!movable[k]) continue;
            for (int move = 0; move < o.moves; ++move) {
                std::vector<uint8_t> trial = inc.pattern;
                if (move == 0)
                    trial[k] ^= 1;
                else {
                    size_t j = move == 1 ? k + 1 : k - 1;
                    if (!trial[k] || j >= n || !solid[j] || trial[j]) continue;
                    trial[k] = 0, trial[j] = 1;
                }
                improved |= inc.consider(trial, 1e-9 * std::max(1.0, std::abs(inc.value)));
            }
        }
        if (!improved) break;
    }
}

}  // namespace

DlpGeometricResult optimiseColumnGeometric(const std::vector<uint8_t>& solid,
                                           const DlpColumnProblem& p,
                                           const DlpGeometricOptions& o) {
    size_t solidLayers = 0;
    for (uint8_t v : solid) solidLayers += v ? 1 : 0;
    if (solidLayers <= std::min<size_t>(o.enumerationLimit, 20))
        return enumerateColumnGeometric(solid, p, o);
    GeometricChainLp patterns(solid, p, o);
    double bound = structuralBound(solid, p, o);
    if (o.relaxationBound) bound = std::max(bound, relaxationBound(solid, p, o));
    Incumbent inc{patterns, {}, {}, INFINITY, {}};
    if (o.start == DlpGeometricStart::ConversionL2) {
        DlpColumnProblem l2 = p;
        l2.penalty = 5.5;
        inc.consider(solveColumnExactly(solid, l2).best.exposed);
    } else {
        // Greedy patterns with the longest gaps d_max allows (and periodic ones, if asked).
        const int window = longestGap(p);
        for (int gap = window; gap > std::max(0, window - o.startGaps); --gap) {
            inc.consider(greedyPattern(solid, p, gap, o));
            for (int skip = bottomSkip(p, gap) - 1;
                 o.periodicStarts && skip <= bottomSkip(p, gap) + 1; ++skip)
                inc.consider(periodicPattern(solid, gap, skip));
        }
    }
    if (!std::isfinite(inc.value))  // fall back to exposing every solid layer
        inc.consider(std::vector<uint8_t>(solid.begin(), solid.end()));
    improveLocally(solid, o, inc);
    if (!std::isfinite(inc.value)) throw InputError("DLP geometric: no printable exposure pattern");
    DlpGeometricResult out = finish(solid, p, o, inc.dose, inc.value, std::min(bound, inc.value));
    out.patterns = patterns.solves();
    out.patternLps = patterns.lpSolves();
    return out;
}

double geometricObjective(const std::vector<uint8_t>& solid, const DlpColumnProblem& p,
                          const DlpGeometricOptions& o, const std::vector<double>& dose) {
    if (dose.size() != solid.size())
        throw InputError("DLP geometric: one dose per layer is needed");
    const double ec = cure::fppGelDose(p.rateConstant, p.gelPoint);
    const double r = std::exp(-p.attenuation * p.layerThickness);
    double carried = 0.0, violation = 0.0, high = -INFINITY, low = INFINITY, light = 0.0;
    for (size_t k = solid.size(); k-- > 0;) {
        carried = dose[k] / ec + r * carried;  // D_k / Ec
        light += dose[k] / ec;
        if (solid[k]) {
            violation += std::max(0.0, 1.0 - carried);
            high = std::max(high, carried), low = std::min(low, carried);
        } else {
            violation += std::max(0.0, carried - (1.0 - o.margin));
        }
    }
    const double spread = high >= low ? high - std::max(low, 0.0) : 0.0;
    return o.violationWeight * violation + o.spreadWeight * spread + 1e-4 * light;
}

DlpGeometricResult enumerateColumnGeometric(const std::vector<uint8_t>& solid,
                                            const DlpColumnProblem& p,
                                            const DlpGeometricOptions& o) {
    std::vector<size_t> layers;
    for (size_t k = 0; k < solid.size(); ++k)
        if (solid[k]) layers.push_back(k);
    if (layers.size() > 20)
        throw InputError("DLP geometric: enumeration is limited to 20 solid layers");
    buildModel(solid, p, o);  // checks the parameters
    GeometricPatternLp model(solid, p, o);
    std::vector<uint8_t> pattern(solid.size(), 0);
    std::vector<double> bestDose, doses;
    double best = std::numeric_limits<double>::infinity();
    for (uint64_t mask = 0; mask < (uint64_t(1) << layers.size()); ++mask) {
        for (size_t i = 0; i < layers.size(); ++i) pattern[layers[i]] = (mask >> i) & 1;
        const double value = model.solve(pattern, doses);
        if (value < best) best = value, bestDose = doses;
    }
    if (!std::isfinite(best)) throw InputError("DLP geometric: no printable exposure pattern");
    DlpGeometricResult out = finish(solid, p, o, bestDose, best, best);  // every pattern: gap 0
    out.patterns = out.patternLps = model.solves();
    return out;
}

DlpGeometricResult branchAndCutColumnGeometric(const std::vector<uint8_t>& solid,
                                               const DlpColumnProblem& p,
                                               const DlpGeometricOptions& o) {
    std::unique_ptr<GeometricModel> model = buildModel(solid, p, o);
    glp_iocp io;
    glp_init_iocp(&io);
    io.msg_lev = GLP_MSG_OFF;
    io.presolve = GLP_ON;
    io.mip_gap = 0.0;
    if (glp_intopt(model->lp.get(), &io) != 0 || glp_mip_status(model->lp.get()) != GLP_OPT)
        throw InputError("DLP geometric: GLPK's branch and cut found no optimum");
    std::vector<double> dose(solid.size(), 0.0);
    for (size_t k = 0; k < solid.size(); ++k)
        if (solid[k]) dose[k] = glp_mip_col_val(model->lp.get(), model->x[k]) * model->ec;
    const double best = glp_mip_obj_val(model->lp.get());
    return finish(solid, p, o, dose, best, best);
}

}  // namespace vpsim::optimise
