#include "vpsim/pipeline/builtins.h"

#include "vpsim/cure/fpp_law.h"
#include "vpsim/cure/threshold_law.h"
#include "vpsim/exporters/cli_exporter.h"
#include "vpsim/exporters/sl1_exporter.h"
#include "vpsim/optimise/dfbtp_strategy.h"
#include "vpsim/optimise/dlp_optimised_mask_planner.h"
#include "vpsim/plan/aces_planner.h"
#include "vpsim/plan/uniform_mask_planner.h"

namespace vpsim::pipeline {

void registerBuiltins(Builtins& b) {
    // Planners.
    plan::registerAcesPlanner(b.planners);
    plan::registerUniformMaskPlanner(b.planners);
    optimise::registerOptimisedMaskPlanner(b.planners);
    optimise::registerLaserOptimisers(b.planners);  // dfbtp, inverse
    // Cure laws.
    cure::registerThresholdLaw(b.cureLaws);
    cure::registerFppLaw(b.cureLaws);
    // Exporters.
    exporters::registerSl1Exporters(b.exporters);
    exporters::registerCliExporter(b.exporters);
}

Builtins makeBuiltins() {
    Builtins builtins;
    registerBuiltins(builtins);
    return builtins;
}

}  // namespace vpsim::pipeline
