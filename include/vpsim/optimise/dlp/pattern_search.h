#pragma once
/// @file
/// The seed 001 column problem solved exactly (Eq. 8 under constraints (i)-(iii), Eq. 10-12).
///
/// Constraint (iii) makes the feasible set a union over exposure patterns (which solid layers
/// get a non-null dose): a dose is 0, or at least the bonding dose of Eq. 10 for the n_z elements
/// down to the previous exposure, and at most d_max. Each pattern's problem is a convex bounded
/// least squares, solved exactly by solveBoundedLeastSquares (active set). The patterns are
/// searched
///  - by enumeration of all 2^s patterns of the s solid layers (small columns; the reference), or
///  - by best-first branch and bound: a node fixes some solid layers to "off" (d = 0) or "on"
///    (d >= the smallest bonding dose any completion allows) and relaxes the undecided ones to
///    0 <= d <= d_max. The relaxation's minimum bounds every completion from below; a relaxed
///    minimiser that satisfies Eq. 10 for its own zero pattern is optimal for the node. Branching
///    is on the lowest layer whose relaxed dose breaks Eq. 10. Each popped node is also rounded
///    to a pattern and solved, for an early incumbent. The search stops when the gap closes or
///    the node budget is spent; then the gap (incumbent - smallest open bound) is reported.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vpsim/optimise/dlp/column.h"

namespace vpsim::optimise {

/// Controls of the exact pattern search.
struct DlpSearchOptions {
    /// Columns with at most this many solid layers are enumerated exhaustively.
    size_t enumerationLimit = 12;
    /// Branch-and-bound nodes per column before stopping with a stated gap.
    size_t maxNodes = 4000;
    /// Stop when (incumbent - bound) <= relativeGap x incumbent.
    double relativeGap = 1e-9;
    /// The incumbent's local search (switch/move one exposure) only visits layers this close to
    /// the bottom of their solid run; it only seeds the bound, so this costs no exactness.
    size_t localSearchDepth = 24;
};

/// A column's optimum with its certificate.
struct DlpSearchResult {
    DlpColumnResult best;     ///< the best feasible pattern's exact solution
    double lowerBound = 0.0;  ///< proven lower bound on F over all feasible patterns
    double gap = 0.0;         ///< (best.objective - lowerBound) / max(best.objective, tiny)
    size_t nodes = 0;         ///< branch-and-bound nodes (or patterns enumerated)
    size_t solves = 0;        ///< bounded least-squares solves
    bool enumerated = false;  ///< true: exhaustive enumeration (gap 0 by construction)
};

/// Smallest dose that bonds an exposure n_z elements above the previous one (Eq. 10), mJ/mm^2.
double bondingDoseFor(const DlpColumnProblem& problem, int elementsBetween);

/// The exact solution of one pattern (active set). @throw InputError when the pattern breaks
/// exposureBounds (an exposed void layer) or cannot be printed (a bonding dose above d_max)
DlpColumnResult solveColumnPattern(const std::vector<uint8_t>& solid,
                                   const std::vector<uint8_t>& exposed,
                                   const DlpColumnProblem& problem);

/// Exhaustive search over every pattern of the solid layers. @throw InputError when the column
/// has more than 24 solid layers (2^24 patterns), or on bad parameters
DlpSearchResult enumerateColumnPatterns(const std::vector<uint8_t>& solid,
                                        const DlpColumnProblem& problem);

/// Branch and bound (file comment). @throw InputError on bad parameters or d_max below d_min
DlpSearchResult branchAndBoundColumn(const std::vector<uint8_t>& solid,
                                     const DlpColumnProblem& problem,
                                     const DlpSearchOptions& options = {});

/// Enumeration when the column is small (options.enumerationLimit), else branch and bound.
/// @throw InputError on bad parameters or d_max below d_min
DlpSearchResult solveColumnExactly(const std::vector<uint8_t>& solid,
                                   const DlpColumnProblem& problem,
                                   const DlpSearchOptions& options = {});

}  // namespace vpsim::optimise
