#pragma once
/// @file
/// Machine-file exporters: a scan plan (with its trajectories where the plan has them) -> a file a
/// printer or its software reads (CLI for laser machines, SL1 for DLP printers, ...). An exporter
/// is created by name from its options section (it parses and checks its own keys) through an
/// ExporterRegistry filled by registerBuiltins(); adding one is a new file pair plus one
/// registration line.

#include <memory>
#include <string>

#include "vpsim/core/registry.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::exporters {

class Exporter {
public:
    virtual ~Exporter() = default;
    /// File name written beside a run's other outputs ("scan.cli", "print.sl1").
    virtual std::string defaultFileName() const = 0;
    /// Whether this exporter can write `plan` (e.g. CLI needs laser vectors or points, SL1
    /// masks); `reason` says why not.
    virtual bool accepts(const plan::ScanPlan& plan, std::string& reason) const = 0;
    /// Writes `plan` to `path` (atomically: a temporary file renamed into place).
    /// @throw InputError when the plan cannot be expressed or the file cannot be written
    virtual void write(const plan::ScanPlan& plan, const std::string& path) const = 0;
};

using ExporterRegistry = Registry<Exporter>;

}  // namespace vpsim::exporters

namespace vpsim::exporters {

/// Writes `plan` with the exporter `name` into `directory` under its default file name and
/// returns the path. @throw InputError when the exporter is unknown or does not accept the plan
std::string exportPlan(const ExporterRegistry& registry, const std::string& name,
                       const ConfigNode& options, const plan::ScanPlan& plan,
                       const std::string& directory);

}  // namespace vpsim::exporters
