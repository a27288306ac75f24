#pragma once
/// @file
/// The geometric programme of one exposure pattern (geometric.h), reduced to its chain of
/// exposures and solved exactly by GLPK: a small LP instead of one row per layer and node.
///
/// With the pattern fixed, only the accumulated doses D_i at the m exposed layers e_1 > ... > e_m
/// (top first) are free: between two exposures no light is added, so every node k below e_i
/// (down to the next exposure) has D_k = r^{e_i - k} D_i, and D_i = x_i + r^{e_{i-1} - e_i}
/// D_{i-1}, the dose box of Eq. 10 becoming a range row on D_i - rho_i D_{i-1}. Inside one such
/// segment the largest solid D is D_i itself (the exposed layer), the smallest the deepest solid
/// node's, a solid node falls short of Ec only if every deeper solid node of the segment does,
/// and a void node exceeds the margin only if every shallower void node does. So the LP starts
/// with one gel row per segment and side (its deepest solid node, its shallowest void node) and
/// adds the rows of the nodes its solution violates until none is: then its optimum is the full
/// programme's (dropped rows only drop non-negative penalties, and none of them is active).
/// About 4 m rows instead of about 4 n: for a 200-layer column exposed every 5th layer, ~40
/// variables instead of ~500.
///
/// Most patterns need no LP at all: when the gel conditions can all be met, the optimum is the
/// least trajectory of a band. For a lower band L >= 1, the constraints D_i >= L r^{-M_i} (M_i:
/// depth of segment i's deepest solid node), D_i - rho_i D_{i-1} in [lo_i, hi_i] are difference
/// constraints on a path, so their least solution l(L) comes from one forward and one backward
/// pass; it is feasible iff it keeps the void nodes' and the top exposure's upper bounds (every
/// feasible point lies above it). Any feasible D with min D = L has max D >= max l(L) and
/// l(L) has min >= L, so the smallest spread is min over L of psi(L) = max_i l_i(L) - L, a convex
/// piecewise-linear function of L (a maximum of affine ones) minimised by golden section on the
/// interval of feasible L. The light term (1e-4 per Ec of dose) is then that of l(L), which is
/// within 1e-4 x the column's dose of the LP's trade-off; patterns whose gel conditions cannot
/// all be met go to the LP.

#include <cstdint>
#include <vector>

#include "vpsim/optimise/dlp/geometric.h"

namespace vpsim::optimise {

/// Solves the pattern's programme; buffers are reused between calls.
class GeometricChainLp {
public:
    /// @throw InputError on bad parameters (as exposureBounds)
    GeometricChainLp(const std::vector<uint8_t>& solid, const DlpColumnProblem& problem,
                     const DlpGeometricOptions& options);

    /// The pattern's optimum objective and doses (mJ/mm^2 per layer): by the band trajectory
    /// when every gel condition can be met, else by the LP; +inf when Eq. 10 cannot be met
    /// within d_max (doses untouched then). @throw InputError when GLPK fails
    double solve(const std::vector<uint8_t>& pattern, std::vector<double>& doses);
    /// The same by the chain LP only (exact, the light term included).
    double solveLp(const std::vector<uint8_t>& pattern, std::vector<double>& doses);
    /// Patterns solved, and how many of them needed the LP.
    size_t solves() const { return mSolves; }
    size_t lpSolves() const { return mLpSolves; }

private:
    /// Fills the chain of `pattern` (mE, mRho, mDeep, mVoid, mDark); false when unprintable.
    bool chain(const std::vector<uint8_t>& pattern);
    /// The band trajectory's objective (doses filled), or -1 when no gel-feasible D exists.
    double band(std::vector<double>& doses);

    std::vector<uint8_t> mSolid;
    DlpColumnProblem mP;
    DlpGeometricOptions mO;
    double mEc = 0.0, mR = 0.0;
    std::vector<double> mLo, mHi;
    size_t mSolves = 0, mLpSolves = 0;
    std::vector<long> mE;       // exposed layers, top first
    std::vector<double> mRho;   // D_i = x_i + rho_i D_{i-1}
    std::vector<int> mDeep;     // depth of the deepest solid node of segment i
    std::vector<int> mVoid;     // depth of the shallowest void node of segment i, -1: none
    double mDarkViolation = 0;  // solid nodes above the top exposure (no light), per Ec x weight
};

}  // namespace vpsim::optimise
