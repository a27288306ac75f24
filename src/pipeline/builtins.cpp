#include "vpsim/pipeline/builtins.h"

#include "vpsim/cure/fpp_law.h"
#include "vpsim/cure/threshold_law.h"
#include "vpsim/exporters/cli_exporter.h"
#include "vpsim/plan/aces_planner.h"
#include "vpsim/plan/uniform_mask_planner.h"

namespace vpsim::pipeline {

void registerBuiltins(Builtins& b) {
    // Planners.
    plan::registerAcesPlanner(b.planners);
    plan::registerUniformMaskPlanner(b.planners);
    // Cure laws.
    cure::registerThresholdLaw(b.cureLaws);
    cure::registerFppLaw(b.cureLaws);
    // Exporters.
    exporters::registerCliExporter(b.exporters);
}

Builtins makeBuiltins() {
    Builtins builtins;
    registerBuiltins(builtins);
    return builtins;
}

}  // namespace vpsim::pipeline
