#include "vpsim/exporters/exporter.h"

namespace vpsim::exporters {

std::string exportPlan(const ExporterRegistry& registry, const std::string& name,
                       const ConfigNode& options, const plan::ScanPlan& plan,
                       const std::string& directory) {
    std::unique_ptr<Exporter> exporter = registry.create(name, options);
    std::string reason;
    if (!exporter->accepts(plan, reason))
        throw InputError("exporter '" + name + "' cannot write this plan: " + reason);
    std::string path = directory + "/" + exporter->defaultFileName();
    exporter->write(plan, path);
    return path;
}

}  // namespace vpsim::exporters
