#pragma once
/// @file
/// The registries of a run's components (planners, cure laws, exporters), filled by
/// registerBuiltins(). There is no global registry: the CLI, a test or a benchmark makes one
/// and passes it down, and may add its own components before loading a job.

#include "vpsim/cure/cure_law.h"
#include "vpsim/exporters/exporter.h"
#include "vpsim/planners/planner.h"

namespace vpsim::pipeline {

struct Builtins {
    planners::PlannerRegistry planners{"planner"};
    cure::CureLawRegistry cureLaws{"cure law"};
    exporters::ExporterRegistry exporters{"exporter"};
};

/// Registers every built-in planner, cure law and exporter (one line each).
void registerBuiltins(Builtins& builtins);

/// A Builtins with registerBuiltins() applied.
Builtins makeBuiltins();

/// One registry's components with their key tables: [{"name", "description", "keys": [...]}]
/// (KeyTable::toJson), sorted by name.
template <class Component>
nlohmann::json registryJson(const Registry<Component>& registry) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& [name, entry] : registry.entries())
        out.push_back(
            {{"name", name}, {"description", entry.description}, {"keys", entry.keys.toJson()}});
    return out;
}

/// Every registered component: {"planners": [...], "cure_laws": [...], "exporters": [...]}.
nlohmann::json componentsJson(const Builtins& builtins);

/// The key tables of every component in Markdown, as examples/README.md carries them between
/// its `<!-- component keys -->` markers (tools/update-key-docs.sh writes them there; a test
/// fails when they differ).
std::string componentsMarkdown(const Builtins& builtins);

}  // namespace vpsim::pipeline
