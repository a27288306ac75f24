#include "vpsim/optimise/dlp/pattern_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <queue>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/cure/cure_model.h"
#include "vpsim/optimise/solvers/bounded_least_squares.h"

namespace vpsim::optimise {
namespace {

enum State : uint8_t { OFF = 0, ON = 1, UNDECIDED = 2 };

Transmission transmissionOf(const DlpColumnProblem& p, size_t layers) {
    return {layers, p.rateConstant, std::exp(-p.attenuation * p.layerThickness)};
}

DlpColumnResult resultFrom(const Transmission& t, const std::vector<uint8_t>& exposed,
                           const BoundedLeastSquaresResult& solved) {
    DlpColumnResult r;
    r.dose = solved.dose;
    r.exposed = exposed;
    r.objective = solved.objective;
    r.iterations = solved.iterations;
    r.converged = solved.converged;
    return r;  // conversion: only for the result handed out (withConversion), a third of the cost
}

/// Fills r.conversion (Phi = 1 - exp(T d)) of a result handed out.
void withConversion(const Transmission& t, DlpColumnResult& r) {
    const std::vector<double> phi = t.apply(r.dose);
    r.conversion.resize(phi.size());
    for (size_t k = 0; k < phi.size(); ++k) r.conversion[k] = -std::expm1(phi[k]);
}

void requirePrintable(const std::vector<uint8_t>& solid, const DlpColumnProblem& p) {
    std::vector<double> lower, upper;
    exposureBounds(std::vector<uint8_t>(solid.size(), 0), solid, p, lower, upper);  // checks p
    const double dMin = bondingDoseFor(p, 1);
    if (p.maxDose < dMin) {
        std::ostringstream reason;
        reason << "DLP column: maximum dose " << p.maxDose * 100.0
               << " mJ/cm^2 is below the bonding dose d_min = " << dMin * 100.0
               << " mJ/cm^2 (Eq. 10), so no layer can be bonded";
        throw InputError(reason.str());
    }
}

/// The search state shared by the nodes of one column.
class ColumnSearch {
public:
    ColumnSearch(const std::vector<uint8_t>& solid, const DlpColumnProblem& p)
        : mSolid(solid),
          mP(p),
          mT(transmissionOf(p, solid.size())),
          mTarget(objectivePhotopolymerisation(solid, p.targetConversion, p.penalty)),
          mRunBegin(solid.size(), 0) {
        for (size_t k = 0; k < solid.size(); ++k)
            if (solid[k]) mRunBegin[k] = (k > 0 && solid[k - 1]) ? mRunBegin[k - 1] : k;
    }

    /// Nearest layer below k in its run whose state is in `states` (bit mask), or -1.
    long nearestBelow(const std::vector<uint8_t>& st, size_t k, int mask) const {
        for (long j = long(k) - 1; j >= long(mRunBegin[k]); --j)
            if ((1 << st[j]) & mask) return j;
        return -1;
    }

    /// Lowest undecided layer in k's run at or below k, or -1.
    long lowestUndecided(const std::vector<uint8_t>& st, size_t k) const {
        for (size_t j = mRunBegin[k]; j <= k; ++j)
            if (st[j] == UNDECIDED) return long(j);
        return -1;
    }

    /// n_z for an exposure at k whose previous exposure below is `below` (-1: none in the run).
    int elementsFor(size_t k, long below) const {
        if (below >= 0) return int(long(k) - below);
        return mP.bonding == Bonding::RunBottom ? int(k - mRunBegin[k] + 1) : 1;
    }

    /// Relaxed bounds of a node; false when an "on" layer cannot bond within d_max.
    bool relaxedBounds(const std::vector<uint8_t>& st, std::vector<double>& lo,
                       std::vector<double>& hi) const {
        const size_t n = st.size();
        lo.assign(n, 0.0);
        hi.assign(n, 0.0);
        for (size_t k = 0; k < n; ++k) {
            if (!mSolid[k] || st[k] == OFF) continue;
            hi[k] = mP.maxDose;
            if (st[k] != ON) continue;
            // Smallest n_z any completion allows: nearest on-or-undecided layer below, or the
            // run's first-exposure rule when every layer below may still be off.
            long below = nearestBelow(st, k, (1 << ON) | (1 << UNDECIDED));
            int nz = elementsFor(k, below);
            if (nearestBelow(st, k, 1 << ON) < 0) nz = std::min(nz, elementsFor(k, -1));
            lo[k] = bondingDoseFor(mP, nz);
            if (lo[k] > mP.maxDose) return false;
        }
        return true;
    }

    /// Lowest layer whose dose breaks Eq. 10 for the solution's own zero pattern, or -1.
    long firstViolation(const std::vector<double>& x) const {
        const double zero = 1e-12 * mP.maxDose;
        for (size_t k = 0; k < x.size(); ++k) {
            if (!mSolid[k] || x[k] <= zero) continue;
            long below = -1;
            for (long j = long(k) - 1; j >= long(mRunBegin[k]); --j)
                if (x[j] > zero) {
                    below = j;
                    break;
                }
            if (x[k] < bondingDoseFor(mP, elementsFor(k, below)) * (1.0 - 1e-12)) return long(k);
        }
        return -1;
    }

    BoundedLeastSquaresResult solve(const std::vector<double>& lo, const std::vector<double>& hi,
                                    const std::vector<double>& start = {}) {
        ++mSolves;
        return solveBoundedLeastSquares(mT, mTarget, lo, hi, start);
    }

    /// Solves pattern `exposed` exactly (warm-started from `start` when given); false when it
    /// cannot be printed.
    bool solvePattern(const std::vector<uint8_t>& exposed, DlpColumnResult& out,
                      const std::vector<double>& start = {}) {
        std::vector<double> lo, hi;
        if (!exposureBounds(exposed, mSolid, mP, lo, hi)) return false;
        out = resultFrom(mT, exposed, solve(lo, hi, start));
        return true;
    }

    /// Layers at most `depth` above the bottom of their run (where patterns matter).
    bool nearRunBottom(size_t k, size_t depth) const {
        return mSolid[k] && k - mRunBegin[k] < depth;
    }

    const std::vector<uint8_t>& solid() const { return mSolid; }
    const DlpColumnProblem& problem() const { return mP; }
    const Transmission& transmission() const { return mT; }
    size_t solves() const { return mSolves; }

private:
    std::vector<uint8_t> mSolid;
    DlpColumnProblem mP;
    Transmission mT;
    std::vector<double> mTarget;
    std::vector<size_t> mRunBegin;
    size_t mSolves = 0;
};

struct Node {
    std::vector<uint8_t> state;
    std::vector<double> dose;  ///< relaxed minimiser
    double bound = 0.0;        ///< relaxed minimum
};

struct NodeOrder {
    bool operator()(const std::shared_ptr<Node>& a, const std::shared_ptr<Node>& b) const {
        return a->bound > b->bound;
    }
};

/// Rounds a relaxed solution to a pattern (a dose above half its own-layer bonding dose is
/// kept) and solves it, as an incumbent candidate.
void tryRounding(ColumnSearch& search, const Node& node, DlpColumnResult& incumbent) {
    const double half = 0.5 * bondingDoseFor(search.problem(), 1);
    std::vector<uint8_t> exposed(node.dose.size(), 0);
    for (size_t k = 0; k < exposed.size(); ++k)
        exposed[k] = search.solid()[k] && node.state[k] != OFF &&
                     (node.state[k] == ON || node.dose[k] >= half);
    DlpColumnResult candidate;
    if (search.solvePattern(exposed, candidate, node.dose) &&
        candidate.objective < incumbent.objective)
        incumbent = std::move(candidate);
}

/// First-improvement local search on an incumbent's pattern: switch one solid layer on or off,
/// or move one exposure a layer up or down, while F decreases.
void improveLocally(ColumnSearch& search, DlpColumnResult& best, int maxPasses, size_t depth) {
    const std::vector<uint8_t>& solid = search.solid();
    const size_t n = solid.size();
    for (int pass = 0; pass < maxPasses; ++pass) {
        bool improved = false;
        for (size_t k = 0; k < n; ++k) {
            if (!search.nearRunBottom(k, depth)) continue;
            for (int move = 0; move < 3; ++move) {
                std::vector<uint8_t> trial = best.exposed;
                if (move == 0)
                    trial[k] ^= 1;  // switch
                else {
                    size_t j = move == 1 ? k + 1 : k - 1;  // move exposure k to j
                    if (!trial[k] || j >= n || !solid[j] || trial[j]) continue;
                    trial[k] = 0, trial[j] = 1;
                }
                DlpColumnResult candidate;
                if (search.solvePattern(trial, candidate, best.dose) &&
                    candidate.objective < best.objective * (1.0 - 1e-13)) {
                    best = std::move(candidate);
                    improved = true;
                }
            }
        }
        if (!improved) break;
    }
}

}  // namespace

double bondingDoseFor(const DlpColumnProblem& p, int elementsBetween) {
    return std::exp(p.attenuation * p.layerThickness * elementsBetween) *
           cure::fppGelDose(p.rateConstant, p.gelPoint);
}

DlpColumnResult solveColumnPattern(const std::vector<uint8_t>& solid,
                                   const std::vector<uint8_t>& exposed,
                                   const DlpColumnProblem& problem) {
    ColumnSearch search(solid, problem);
    DlpColumnResult result;
    if (!search.solvePattern(exposed, result))
        throw InputError(
            "DLP column: an exposure in this pattern needs more than the maximum dose to bond "
            "(Eq. 10)");
    withConversion(search.transmission(), result);
    return result;
}

DlpSearchResult enumerateColumnPatterns(const std::vector<uint8_t>& solid,
                                        const DlpColumnProblem& problem) {
    requirePrintable(solid, problem);
    std::vector<size_t> solidLayers;
    for (size_t k = 0; k < solid.size(); ++k)
        if (solid[k]) solidLayers.push_back(k);
    if (solidLayers.size() > 24)
        throw InputError("DLP column: enumeration is limited to 24 solid layers");
    ColumnSearch search(solid, problem);
    DlpSearchResult out;
    out.enumerated = true;
    out.best.objective = std::numeric_limits<double>::infinity();
    std::vector<uint8_t> exposed(solid.size(), 0);
    for (uint64_t mask = 0; mask < (uint64_t(1) << solidLayers.size()); ++mask) {
        for (size_t i = 0; i < solidLayers.size(); ++i) exposed[solidLayers[i]] = (mask >> i) & 1;
        DlpColumnResult candidate;
        ++out.nodes;
        if (search.solvePattern(exposed, candidate) && candidate.objective < out.best.objective)
            out.best = std::move(candidate);
    }
    out.lowerBound = out.best.objective;
    out.solves = search.solves();
    withConversion(search.transmission(), out.best);
    return out;
}

DlpSearchResult branchAndBoundColumn(const std::vector<uint8_t>& solid,
                                     const DlpColumnProblem& problem,
                                     const DlpSearchOptions& options) {
    requirePrintable(solid, problem);
    ColumnSearch search(solid, problem);
    DlpSearchResult out;
    // Incumbent: every solid layer exposed (always printable once d_max >= d_min(1)).
    std::vector<uint8_t> all(solid.begin(), solid.end());
    for (auto& v : all) v = v ? 1 : 0;
    search.solvePattern(all, out.best);
    bool locallyImproved = false;

    std::priority_queue<std::shared_ptr<Node>, std::vector<std::shared_ptr<Node>>, NodeOrder> open;
    auto makeNode = [&](std::vector<uint8_t> state, const std::vector<double>& warm) {
        std::vector<double> lo, hi;
        if (!search.relaxedBounds(state, lo, hi)) return;
        auto node = std::make_shared<Node>();
        node->state = std::move(state);
        BoundedLeastSquaresResult relaxed = search.solve(lo, hi, warm);
        node->dose = std::move(relaxed.dose);
        node->bound = relaxed.objective;
        open.push(std::move(node));
    };
    std::vector<uint8_t> root(solid.size(), OFF);
    for (size_t k = 0; k < solid.size(); ++k)
        if (solid[k]) root[k] = UNDECIDED;
    makeNode(root, {});
    double bound = out.best.objective;
    while (!open.empty()) {
        std::shared_ptr<Node> node = open.top();
        const double tolerance = options.relativeGap * std::max(out.best.objective, 1e-300);
        if (node->bound >= out.best.objective - tolerance) break;  // nothing open can improve
        if (out.nodes >= options.maxNodes) break;
        open.pop();
        ++out.nodes;
        long k = search.firstViolation(node->dose);
        if (k >= 0 && !locallyImproved) {  // the root is not printable: find a good incumbent
            improveLocally(search, out.best, 20, options.localSearchDepth);
            locallyImproved = true;
        }
        if (k < 0) {  // the relaxed minimiser is printable: the node's optimum
            std::vector<uint8_t> exposed(solid.size(), 0);
            for (size_t i = 0; i < solid.size(); ++i)
                exposed[i] = solid[i] && node->dose[i] > 1e-12 * problem.maxDose;
            DlpColumnResult candidate;
            if (search.solvePattern(exposed, candidate) && candidate.objective < out.best.objective)
                out.best = std::move(candidate);
            continue;
        }
        tryRounding(search, *node, out.best);
        // Branch bottom-up: the lowest undecided layer of the violating layer's run at or below
        // it, so that decided prefixes fix n_z exactly and unprintable ones are pruned at once.
        k = search.lowestUndecided(node->state, size_t(k));
        if (k < 0) continue;  // cannot happen with consistent bounds; drop the node
        for (uint8_t choice : {OFF, ON}) {
            std::vector<uint8_t> child = node->state;
            child[k] = choice;
            makeNode(std::move(child), node->dose);
        }
    }
    bound = open.empty() ? out.best.objective : std::min(out.best.objective, open.top()->bound);
    out.lowerBound = bound;
    out.gap = (out.best.objective - bound) / std::max(out.best.objective, 1e-300);
    out.solves = search.solves();
    withConversion(search.transmission(), out.best);
    return out;
}

DlpSearchResult solveColumnExactly(const std::vector<uint8_t>& solid,
                                   const DlpColumnProblem& problem,
                                   const DlpSearchOptions& options) {
    size_t solidLayers = 0;
    for (uint8_t v : solid) solidLayers += v ? 1 : 0;
    if (solidLayers <= std::min<size_t>(options.enumerationLimit, 24))
        return enumerateColumnPatterns(solid, problem);
    return branchAndBoundColumn(solid, problem, options);
}

}  // namespace vpsim::optimise
