#pragma once
/// @file
/// The `plan` keys every laser strategy accepts (ACES parameters that DFBTP and the inverse
/// planner reuse, border scans, scan order and direction), so `--set plan.strategy=...` switches
/// strategy on one job. Each laser planner's key table starts with laserPlanKeyTable() and its
/// factory calls readLaserPlanOptions().

#include <nlohmann/json.hpp>

#include "vpsim/core/key_table.h"
#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/plan/aces/aces.h"
#include "vpsim/plan/machine/part_order.h"
#include "vpsim/plan/machine/scan_direction.h"

namespace vpsim::planners {

struct LaserPlanOptions {
    /// The ACES keys: homogeneity, edge, border_count, border_offset. The beam, machine and dose
    /// fields are filled by acesParameters().
    plan::AcesParameters aces;
    plan::DirectionRule direction;                      ///< `direction`: per layer
    plan::OrderMethod order = plan::OrderMethod::Auto;  ///< `order` of the parts
};

/// The shared laser keys; `edgeDefault` is the strategy's default edge rule.
KeyTable laserPlanKeyTable(plan::AcesEdge edgeDefault = plan::AcesEdge::SeedFivePercent);

/// @throw InputError naming the file and key
LaserPlanOptions readLaserPlanOptions(const KeyReader& keys);

/// ACES parameters for a fitted beam, the machine and the cure law's critical dose (mJ/mm^2).
/// The target is asked of the delivered dose, so Ec is divided by the beam's efficiency.
plan::AcesParameters acesParameters(const LaserPlanOptions& options, const kernel::FittedBeam& beam,
                                    const plan::Machine& machine, double criticalDose);

/// Called by every laser planner before it plans: refuses a job whose ACES target dose (from
/// `aces`, acesParameters()) a field of lines at the largest hatch spacing cannot get within the
/// machine's power range at its process speed (plan::checkDoseReachable).
/// @throw InputError in one line saying what to change
void checkLaserDose(const plan::AcesParameters& aces, const plan::Machine& machine);

/// Fraction of the critical dose below which one vector's or dot's own peak dose is negligible
/// (plan::LaserLimits::negligibleDose): 1%.
constexpr double NEGLIGIBLE_FRACTION_OF_EC = 0.01;

/// Called by every laser planner at the end of plan(): fits the plan to the machine's limits
/// (plan::fitPlanToLimits with the beam of `aces` and 1% of its critical dose as negligible;
/// `dotPitch` mm, 0 for a plan without a dot grid). Returns {"laser": LimitFit::toJson()} for
/// the planner's summary (report.json's "laser", which the scan stage completes).
nlohmann::json fitLaserPlan(plan::ScanPlan& plan, const plan::AcesParameters& aces,
                            const plan::Machine& machine, double dotPitch);

}  // namespace vpsim::planners
