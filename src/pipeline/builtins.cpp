#include "vpsim/pipeline/builtins.h"

#include "vpsim/cure/fpp_law.h"
#include "vpsim/cure/threshold_law.h"
#include "vpsim/exporters/cli_exporter.h"
#include "vpsim/exporters/png_stack_exporter.h"
#include "vpsim/exporters/sl1_exporter.h"
#include "vpsim/planners/aces_planner.h"
#include "vpsim/planners/dfbtp_planner.h"
#include "vpsim/planners/inverse_planner.h"
#include "vpsim/planners/optimised_mask_planner.h"
#include "vpsim/planners/uniform_mask_planner.h"

namespace vpsim::pipeline {

void registerBuiltins(Builtins& b) {
    // Planners.
    planners::registerAcesPlanner(b.planners);
    planners::registerUniformMaskPlanner(b.planners);
    planners::registerOptimisedMaskPlanner(b.planners);
    planners::registerDfbtpPlanner(b.planners);
    planners::registerInversePlanner(b.planners);
    // Cure laws.
    cure::registerThresholdLaw(b.cureLaws);
    cure::registerFppLaw(b.cureLaws);
    // Exporters.
    exporters::registerSl1Exporter(b.exporters);
    exporters::registerPngStackExporter(b.exporters);
    exporters::registerCliExporter(b.exporters);
}

nlohmann::json componentsJson(const Builtins& b) {
    return {{"planners", registryJson(b.planners)},
            {"cure_laws", registryJson(b.cureLaws)},
            {"exporters", registryJson(b.exporters)}};
}

namespace {

template <class Component>
std::string registryMarkdown(const Registry<Component>& registry, const std::string& section,
                             const std::string& title) {
    std::string out;
    for (const auto& [name, entry] : registry.entries()) {
        out += "### " + title + " `" + name + "` (`" + section + "`)\n\n" + entry.description +
               ".\n\n";
        out += entry.keys.keys().empty() ? "No keys.\n" : entry.keys.markdown();
        out += "\n";
    }
    return out;
}

}  // namespace

std::string componentsMarkdown(const Builtins& b) {
    return registryMarkdown(b.planners, "plan", "Planner") +
           registryMarkdown(b.cureLaws, "cure", "Cure law") +
           registryMarkdown(b.exporters, "export", "Exporter");
}

Builtins makeBuiltins() {
    Builtins builtins;
    registerBuiltins(builtins);
    return builtins;
}

}  // namespace vpsim::pipeline
