#pragma once
/// @file
/// Building blocks of the geometric column search (geometric.h): the LP of one exposure
/// pattern (GLPK's simplex, built once per column and re-solved from the previous basis) and the
/// start patterns the search refines.
///
/// Why a periodic start: every exposure raises the accumulated dose by at least its bonding
/// dose, e^{mu Le n_z} Ec >= Ec / r, on top of r times the dose from above, so exposing every
/// layer of a long run drives D towards Ec / (r (1 - r)) (about 9 Ec for the seed 001 resin)
/// while the bottom of a run above a void must stay near Ec (the void below it must stay under
/// (1 - margin) Ec). Exposing every g-th layer (g up to the longest gap d_max allows) keeps D
/// near r^{-g} / (1 - r^g) Ec at an exposure (about 4 Ec for g = 5), which is what the
/// uniformity term wants; the layers at a run's bottom are left to the print-through.

#include <cstdint>
#include <memory>
#include <vector>

#include "vpsim/optimise/dlp/geometric.h"

namespace vpsim::optimise {

/// The LP of one exposure pattern of a column: the doses' boxes come from exposureBounds, all
/// else (print-through recursion, soft gel conditions, spread bounds) is fixed, so only bounds
/// change between patterns and GLPK's dual simplex restarts from the previous basis.
class GeometricPatternLp {
public:
    /// @throw InputError on bad parameters (as exposureBounds)
    GeometricPatternLp(const std::vector<uint8_t>& solid, const DlpColumnProblem& problem,
                       const DlpGeometricOptions& options);
    ~GeometricPatternLp();
    GeometricPatternLp(const GeometricPatternLp&) = delete;
    GeometricPatternLp& operator=(const GeometricPatternLp&) = delete;

    /// The pattern's optimum objective and doses (mJ/mm^2); +inf when Eq. 10 cannot be met
    /// within d_max (doses untouched then).
    double solve(const std::vector<uint8_t>& pattern, std::vector<double>& doses);
    /// Patterns solved so far (LPs, not counting the ones exposureBounds rejected).
    size_t solves() const { return mSolves; }

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
    size_t mSolves = 0;
};

/// The solid runs [bottom, top] (layer indices, inclusive) of a column, bottom first.
std::vector<std::pair<size_t, size_t>> solidRuns(const std::vector<uint8_t>& solid);

/// Start pattern: in every run the top layer, and every `gap`-th layer from `skip` layers above
/// the run's bottom upwards (runs on the platform, layer 0, start at their bottom); runs with
/// no more than `skip` layers only their top. @throw InputError when gap < 1
std::vector<uint8_t> periodicPattern(const std::vector<uint8_t>& solid, int gap, int skip);

/// Start pattern built from the top of the column down with minimal doses: each run's top is
/// exposed, then every `gap`-th layer, until the print-through of an exposure within the next
/// gap can cure the run down to its bottom (light from the runs above counts); of those layers
/// the one with the smallest weighted peak dose plus void overshoot below the run becomes the
/// lowest exposure. Under run-bottom bonding it stays within the longest gap of the bottom.
/// @throw InputError when gap < 1 or d_max is below the bonding dose
std::vector<uint8_t> greedyPattern(const std::vector<uint8_t>& solid,
                                   const DlpColumnProblem& problem, int gap,
                                   const DlpGeometricOptions& options = {});

/// A lower bound on the geometric objective of every pattern, from the column's structure
/// (the MILP's LP relaxation is near 0: fractional on/off variables let tiny doses keep D at Ec
/// everywhere). Per solid run, either its top layer is left dark (a shortfall of at least
/// 1 - r (1 - margin) there) or, with e its lowest exposure, D_e >= the bonding dose of e plus
/// sum_{i < m} r^{i w} (each of the m >= ceil((top - e) / w) exposures above bonds down to the
/// previous one, gaps w at most the longest), so spread >= D_e (1 - r^{e - bottom}) and the gel
/// and void conditions at and below the bottom are charged for D_bottom = r^{e - bottom} D_e.
/// With B_R a run's least cost over these cases and V_R its least violation cost alone, the
/// objective is at least max_R B_R + the other runs' V (violations add up, the spread is
/// shared). The light term and the runs' interiors are left out: a bound, not an estimate.
/// @throw InputError when d_max is below the bonding dose
double structuralBound(const std::vector<uint8_t>& solid, const DlpColumnProblem& problem,
                       const DlpGeometricOptions& options);

/// The longest gap n_z between exposures that d_max allows (Eq. 10), and the number of bottom
/// layers a run above a void leaves to the print-through of a gap-`gap` periodic pattern
/// (r^skip D_exposure >= Ec). @throw InputError when d_max is below the bonding dose
int longestGap(const DlpColumnProblem& problem);
int bottomSkip(const DlpColumnProblem& problem, int gap);

}  // namespace vpsim::optimise
