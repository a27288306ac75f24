#pragma once
/// @file
/// `objective: geometric` for a DLP pixel column: aim at the shape, not at a conversion profile.
///
/// Every node inside the part must reach the gel dose Ec (D_p >= Ec, i.e. Phi >= Phi_c), every
/// node outside must stay below it with a margin (D_p <= (1 - margin) Ec), and the accumulated
/// dose inside is as uniform as the remaining freedom allows (minimise max - min of D inside,
/// i.e. of the conversion, which is monotone in D), keeping d <= d_max and Eq. 10 under either
/// reading. The gel conditions are soft with a large weight (violation in units of Ec x
/// `violationWeight`), because some cannot be met at all: under run-bottom bonding the first
/// exposure of a run cures down to the designed surface, so the node just below it reaches Ec.
///
/// The column is a mixed-integer linear programme (below). GLPK's own branch and cut (Debian
/// libglpk) took over 5 s per 220-layer column without closing its gap, so the exposure pattern
/// is searched instead (optimiseColumnGeometric): greedy start patterns built from the top down
/// (geometric_lp.h: every gap-th layer, the run's lowest exposure where its print-through
/// cures the run's bottom), then single-layer switches near each run's bottom. Each pattern's
/// programme is solved exactly by its chain of exposures (geometric_chain.h: a small LP, or
/// no LP when every gel condition can be met), tested against GLPK on the full per-layer LP; the
/// reported gap is against a structural lower bound (structuralBound), since the MILP's LP
/// relaxation is near 0. Up to enumerationLimit solid layers every pattern is enumerated (gap 0).
/// MILP variables: doses x_p = d_p / Ec and on/off z_p per solid layer, accumulated doses D_p by
/// the print-through recursion D_p = x_p + r D_{p+1}, slacks, and the spread bounds. Eq. 10 with
/// n_z = k is linear in z: x_q >= e^{mu Le k} (z_q + z_{q-k} - 1 - sum of the z between), for
/// every gap k that d_max allows; longer gaps are forbidden by window rows using a monotone
/// "exposed at or below" indicator. Units: dose mJ/mm^2.

#include <cstdint>
#include <vector>

#include "vpsim/optimise/dlp/column.h"

namespace vpsim::optimise {

/// Where the pattern search starts: greedy (and optionally periodic) patterns
/// (geometric_lp.h), or the conversion-l2 optimum's pattern (the earlier default, kept as the
/// reference the benchmark compares with: it costs a branch and bound per column and leaves long
/// runs' interiors exposed at every layer, D near Ec / (r (1 - r)), about 9 Ec).
enum class DlpGeometricStart { Greedy, ConversionL2 };

/// Controls of the geometric column programme.
struct DlpGeometricOptions {
    double margin = 0.05;            ///< outside nodes stay below (1 - margin) Ec, in [0, 1)
    double violationWeight = 100.0;  ///< weight of gel-condition violations (per Ec) vs spread
    double spreadWeight = 1.0;       ///< weight of the spread max - min of D inside (per Ec)
    DlpGeometricStart start = DlpGeometricStart::Greedy;  ///< the search's start pattern
    int maxPasses = 2;    ///< local-search passes over the exposure pattern
    int moves = 1;        ///< 1: switch a layer on/off; 3: also move an exposure +-1
    int searchDepth = 4;  ///< layers above each run's bottom the local search moves
    /// Also compute the MILP's LP relaxation as a lower bound (weak: near 0, and one large LP
    /// per column); the structural bound (geometric_lp.h) is always computed.
    bool relaxationBound = false;
    int startGaps = 2;            ///< start patterns for gaps window, window - 1, ... (this many)
    bool periodicStarts = false;  ///< also the periodic start patterns (3 per gap)
    /// Columns with at most this many solid layers are solved by enumerating every pattern
    /// (exact, gap 0); 2^limit LPs.
    size_t enumerationLimit = 10;
};

/// Result of the geometric programme for one column.
struct DlpGeometricResult {
    std::vector<double> dose;         ///< d_p, mJ/mm^2
    std::vector<double> accumulated;  ///< D_p at each layer's top node, mJ/mm^2
    double violation = 0.0;           ///< sum of gel-condition violations, in units of Ec
    double spread = 0.0;              ///< max - min of D inside, in units of Ec
    double objective = 0.0;           ///< the programme's objective
    double lowerBound = 0.0;          ///< no pattern does better (structural bound, or exact)
    double gap = 0.0;                 ///< (objective - lowerBound) / |objective|
    bool optimal = false;             ///< gap closed (the bound is attained)
    size_t patterns = 0;              ///< exposure patterns solved
    size_t patternLps = 0;            ///< of which by an LP (the others by the band trajectory)
};

/// The programme's objective for doses `dose` (mJ/mm^2 per layer), computed directly from the
/// print-through recursion: violationWeight x (sum of gel violations, per Ec) + spreadWeight x
/// (max - min of D/Ec inside) + 1e-4 x (sum of doses, per Ec). Eq. 10 is not checked here.
/// @throw InputError when the sizes differ
double geometricObjective(const std::vector<uint8_t>& solid, const DlpColumnProblem& problem,
                          const DlpGeometricOptions& options, const std::vector<double>& dose);

/// The exact optimum by enumeration of every exposure pattern of the solid layers, each
/// pattern's LP solved by GLPK's simplex (gap 0, optimal). @throw InputError beyond 20 solid
/// layers, or as optimiseColumnGeometric
DlpGeometricResult enumerateColumnGeometric(const std::vector<uint8_t>& solid,
                                            const DlpColumnProblem& problem,
                                            const DlpGeometricOptions& options = {});

/// The exact optimum of the same MILP by GLPK's branch and cut (glp_intopt, zero gap): the
/// reference the enumeration is tested against (slow beyond a few dozen layers).
/// @throw InputError when GLPK finds no optimum
DlpGeometricResult branchAndCutColumnGeometric(const std::vector<uint8_t>& solid,
                                               const DlpColumnProblem& problem,
                                               const DlpGeometricOptions& options = {});

/// Solves the geometric programme for one column (solid[k] != 0: layer k in the part): by
/// enumeration (exact) up to options.enumerationLimit solid layers, else by the local search
/// with the structural bound and its gap.
/// `problem.targetConversion` and `penalty` are not used; bonding, d_max, K, mu, Phi_c are.
/// @throw InputError on bad parameters, d_max below the bonding dose, or when GLPK fails
DlpGeometricResult optimiseColumnGeometric(const std::vector<uint8_t>& solid,
                                           const DlpColumnProblem& problem,
                                           const DlpGeometricOptions& options = {});

}  // namespace vpsim::optimise
