#pragma once
/// @file
/// The `plan` keys every laser strategy accepts (ACES parameters that DFBTP and the inverse
/// planner reuse, border scans, scan order and direction), so `--set plan.strategy=...` switches
/// strategy on one job. Each laser planner's factory calls readLaserPlanOptions(), which claims
/// these keys; a key that belongs to no strategy in use stays an unknown-key error.

#include <vector>

#include "vpsim/core/registry.h"
#include "vpsim/kernel/fitted_beam.h"
#include "vpsim/plan/aces.h"
#include "vpsim/plan/part_order.h"
#include "vpsim/plan/scan_direction.h"

namespace vpsim::plan {

struct LaserPlanOptions {
    /// The ACES keys (plan::readAcesKeys): homogeneity, edge, border_count, border_offset.
    /// The beam, machine and dose fields are filled by acesParameters().
    AcesParameters aces;
    DirectionRule direction;                ///< `direction`: scan direction per layer
    OrderMethod order = OrderMethod::Auto;  ///< `order` of the parts (the pipeline's trajectories)
};

/// @throw InputError naming the file and key
LaserPlanOptions readLaserPlanOptions(const ConfigNode& plan);

/// The keys readLaserPlanOptions() reads, for `vpsim plan --list`.
std::vector<ConfigKeyDoc> laserPlanKeys();

/// ACES parameters for a fitted beam, the machine and the cure law's critical dose (mJ/mm^2).
/// The target is asked of the delivered dose, so Ec is divided by the beam's efficiency.
AcesParameters acesParameters(const LaserPlanOptions& options, const kernel::FittedBeam& beam,
                              const Machine& machine, double criticalDose);

}  // namespace vpsim::plan
