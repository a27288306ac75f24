#include "vpsim/exporters/export_file.h"

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"

namespace vpsim::exporters {

std::string fileExtension(const std::string& path) {
    const size_t dot = path.find_last_of('.'), slash = path.find_last_of('/');
    return dot == std::string::npos || (slash != std::string::npos && dot < slash)
               ? std::string()
               : path.substr(dot);
}

std::string chooseExporter(const ExporterRegistry& registry, const ExportRequest& request) {
    if (!request.exporter.empty()) return request.exporter;
    std::string reasons;
    for (const auto& [name, entry] : registry.entries()) {
        try {
            auto exporter =
                registry.create(name, ConfigNode(request.options, request.optionsSource));
            if (fileExtension(exporter->defaultFileName()) == fileExtension(request.path))
                return name;
        } catch (const InputError& e) {
            reasons +=
                "; " + name + ": " + (e.key().empty() ? "" : "key '" + e.key() + "' ") + e.reason();
        }
    }
    throw InputError("no exporter writes '" + fileExtension(request.path) +
                         "' files with these options (give " + request.hint + ")" + reasons,
                     request.path);
}

nlohmann::json exportToFile(const ExporterRegistry& registry, const plan::ScanPlan& plan,
                            const ExportRequest& request) {
    const std::string name = chooseExporter(registry, request);
    ConfigNode section(request.options, request.optionsSource);
    auto exporter = registry.create(name, section);
    section.checkUnknownKeys();
    std::string reason;
    if (!exporter->accepts(plan, reason))
        throw InputError(name + ": " + reason,
                         request.planSource.empty() ? request.path : request.planSource);
    exporter->write(plan, request.path);
    size_t vectors = 0;
    bool dlp = false;
    for (const auto& layer : plan.layers) {
        vectors += layer.vectors.size();
        dlp = dlp || !layer.masks.empty();
    }
    nlohmann::json summary = {{"file", request.path},
                              {"exporter", name},
                              {"options", request.options},
                              {"layers", plan.layers.size()},
                              {"vectors", vectors}};
    if (!dlp) summary["build_time_s"] = plan::estimateBuildTime(plan, request.timing).toJson();
    return summary;
}

}  // namespace vpsim::exporters
