#pragma once
/// @file
/// The registries of a run's components (planners, cure laws, exporters), filled by
/// registerBuiltins(). There is no global registry: the CLI, a test or a benchmark makes one
/// and passes it down, and may add its own components before loading a job.

#include "vpsim/cure/cure_law.h"
#include "vpsim/exporters/exporter.h"
#include "vpsim/plan/planner.h"

namespace vpsim::pipeline {

struct Builtins {
    plan::PlannerRegistry planners{"planner"};
    cure::CureLawRegistry cureLaws{"cure law"};
    exporters::ExporterRegistry exporters{"exporter"};
};

/// Registers every built-in planner, cure law and exporter (one line each).
void registerBuiltins(Builtins& builtins);

/// A Builtins with registerBuiltins() applied.
Builtins makeBuiltins();

}  // namespace vpsim::pipeline
