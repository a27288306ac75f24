#pragma once
/// @file
/// Greyscale DLP dose optimisation for one pixel column (seed 001 Section 3, Eq. 5-12).
///
/// The column is discretised along Z with one node per layer at the layer's top surface (where
/// that layer's mask exposure d_k is applied; element length Le = layer thickness). With the
/// linearising variable phi = ln(1 - Phi) (Eq. 6) the FPP model (Eq. 1) plus print-through
/// (Eq. 4) is linear in the doses (Eq. 5, 7):
///     phi = T d,   T_pr = -K exp(-mu (r - p) Le) for r >= p (layer r exposed after p), else 0.
/// Layers are numbered in build order (0 = first, at the bottom) and light from each later
/// exposure reaches the earlier layers below it. (Eq. 7 as printed has p >= r: it numbers the
/// nodes the other way round, which contradicts Eq. 5 as printed; the physics is the same.)
/// The doses minimise F(d) = ||T d - phi_obj||^2 (Eq. 8) by projected gradient descent
/// (Eq. 9, gradient 2 T^T (T d - phi_obj)) subject to (Section 3.2):
///   (i) d >= 0, (ii) d <= d_max, (iii) every non-null dose bonds its layer to the last exposed
///   layer below (Eq. 10): d >= exp(mu Le n_z) ln(1/(1-Phi_c)) / K with n_z the number of
///   elements between them; layers outside the part get no exposure at all. We read "the
///   previously built-up layer" within one solid run of the column: the first exposure of a run
///   bonds down to the run's bottom surface (the platform or the designed down-facing surface).
/// Targets (Eq. 11-12): phi_obj = ln(1 - Phi_obj) at nodes inside the part and the penalty
/// coefficient a >= 0 at nodes outside it (a > 0 is unreachable, since phi <= 0, and pushes the
/// print-through into void nodes down; the paper recommends a > 5 and uses 5.5).
/// Units: dose mJ/mm^2, lengths mm, K mm^2/mJ, mu 1/mm.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vpsim::optimise {

/// How Eq. 10 reads for the first exposure of a solid run above a void (or the platform):
/// `RunBottom`: it must cure down to the run's designed bottom surface (n_z counts every element
/// from that surface up to it); `OwnLayer`: it only bonds its own layer (n_z = 1), and unexposed
/// layers below it are cured (or not) by print-through alone. Later exposures of a run always
/// bond to the previous exposure below them, n_z elements down.
enum class Bonding { OwnLayer, RunBottom };

/// Parameters of a DLP column optimisation.
struct DlpColumnProblem {
    double layerThickness = 0.05;    ///< Le, mm (> 0)
    double rateConstant = 0.0;       ///< K, mm^2/mJ (> 0)
    double attenuation = 0.0;        ///< mu = 1/Dp, 1/mm (> 0)
    double gelPoint = 0.0;           ///< Phi_c in (0, 1)
    double maxDose = 0.0;            ///< d_max per layer, mJ/mm^2 (>= the bonding dose)
    double targetConversion = 0.95;  ///< Phi_obj inside the part, in (0, 1)
    double penalty = 5.5;            ///< a of Eq. 12 (>= 0): phi_obj at nodes outside the part
    /// Reading of Eq. 10 for a run's first exposure. Default own-layer: it reproduces seed 001
    /// Table 2's optimised measurements (all four features within 0.18 mm), run-bottom does not
    /// (0.39 mm off); see tests/optimise/test_dlp_table2.cpp.
    Bonding bonding = Bonding::OwnLayer;
};

/// Iteration control of the projected gradient descent.
struct DlpOptimiserOptions {
    int maxIterations = 200000;
    /// Stop when no dose changes by more than tolerance x the largest dose in one iteration.
    double tolerance = 1e-12;
    /// Passes of the coordinate search over exposure patterns (optimiseColumnDoses).
    int maxSweeps = 3;
};

/// Optimised doses and the resulting conversion of a column.
struct DlpColumnResult {
    std::vector<double> dose;        ///< d_k per layer, mJ/mm^2 (0 outside the part)
    std::vector<double> conversion;  ///< Phi_k = 1 - exp((T d)_k) at each layer's top node
    std::vector<uint8_t> exposed;    ///< layers with a non-null dose
    double objective = 0.0;          ///< F(d) of Eq. 8
    int iterations = 0;              ///< gradient steps of the final pattern's solve
    bool converged = false;
};

/// Eq. 10: smallest dose that bonds a layer to the exposed layer `elementsBetween` layers below
/// (n_z), d_min = exp(mu Le n_z) ln(1/(1-Phi_c)) / K. @throw InputError on bad parameters
double bondingDose(double rateConstant, double attenuation, double gelPoint, double layerThickness,
                   int elementsBetween = 1);

/// Eq. 7: the n x n transmission matrix, row-major (T[p * n + r]). For tests and inspection;
/// the optimiser applies T in O(n) by recursion instead.
std::vector<double> transmissionMatrix(size_t layers, double layerThickness, double rateConstant,
                                       double attenuation);

/// phi = T d in O(n) (print-through recursion scaled by -K). @throw InputError on a negative dose
std::vector<double> applyTransmission(const std::vector<double>& dose, double layerThickness,
                                      double rateConstant, double attenuation);

/// T^T v in O(n).
std::vector<double> applyTransmissionTransposed(const std::vector<double>& v, double layerThickness,
                                                double rateConstant, double attenuation);

/// Eq. 11-12: phi_obj per layer, ln(1 - targetConversion) where solid[k] != 0, else penalty.
std::vector<double> objectivePhotopolymerisation(const std::vector<uint8_t>& solid,
                                                 double targetConversion, double penalty);

/// Bounds of each layer's dose for an exposure pattern (exposed[k] != 0: layer k gets a non-null
/// dose; only solid layers may be exposed). An exposed layer must bond (Eq. 10) through the n_z
/// elements down to the previous exposed layer of its solid run, or, for the run's first
/// exposure, to the run's bottom surface (Bonding::RunBottom) or only its own layer (OwnLayer):
/// lower = exp(mu Le n_z) ln(1/(1-Phi_c)) / K, upper = d_max; unexposed layers have 0..0.
/// @return false when some lower bound exceeds d_max (the pattern cannot be printed)
/// @throw InputError on bad parameters, a length mismatch or an exposed void layer
bool exposureBounds(const std::vector<uint8_t>& exposed, const std::vector<uint8_t>& solid,
                    const DlpColumnProblem& problem, std::vector<double>& lower,
                    std::vector<double>& upper);

/// Minimises Eq. 8 for a fixed exposure pattern by projected gradient descent (Eq. 9) inside
/// the bounds of exposureBounds: a convex problem, so the result is its global minimum.
/// @throw InputError as exposureBounds, or when the pattern is infeasible
DlpColumnResult optimiseColumnDosesForPattern(const std::vector<uint8_t>& solid,
                                              const std::vector<uint8_t>& exposed,
                                              const DlpColumnProblem& problem,
                                              const DlpOptimiserOptions& options = {});

/// Optimises the per-layer doses of one pixel column (solid[k] != 0: layer k belongs to the
/// part). Constraint (iii) makes the feasible set non-convex (a dose is 0 or at least its bonding
/// dose), so the exposure pattern is searched: for each solid run, how many of its bottom
/// layers are left unexposed and cured by the print-through of the layers above (which is what
/// lets a down-facing surface stop at its designed height), by coordinate sweeps over the runs,
/// each candidate solved by optimiseColumnDosesForPattern. The search is a heuristic: the best
/// pattern found, not a proven global optimum. Cost: O(layers^2 x iterations) per column.
/// @throw InputError on bad parameters or when d_max is below the bonding dose d_min
DlpColumnResult optimiseColumnDoses(const std::vector<uint8_t>& solid,
                                    const DlpColumnProblem& problem,
                                    const DlpOptimiserOptions& options = {});

}  // namespace vpsim::optimise
