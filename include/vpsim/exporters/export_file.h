#pragma once
/// @file
/// Writing a plan to a file the user names (`vpsim export`, the Python module's vpsim.export):
/// the exporter by name, else by the file's extension, and the summary both report.

#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/exporters/exporter.h"
#include "vpsim/plan/machine/build_time.h"

namespace vpsim::exporters {

/// The extension of `path`'s file name (".cli"), "" when it has none.
std::string fileExtension(const std::string& path);

struct ExportRequest {
    std::string path;  ///< the file to write
    std::string
        exporter;  ///< registered name; "" = the one whose default file has path's extension
    nlohmann::json options = nlohmann::json::object();  ///< the exporter's section
    std::string optionsSource = "options";  ///< names the options in messages ("command line")
    /// How the caller names an exporter and its options, for the error when none matches
    /// ("--exporter NAME and its --option KEY=VALUE").
    std::string hint = "an exporter and its options";
    std::string planSource;         ///< names the plan in messages (its file; "" = path)
    plan::BuildTimeOptions timing;  ///< machine limits for the laser build-time estimate
};

/// The exporter `request` names, else the registered one whose default file has the path's
/// extension, each created from the options (those the options do not suit are skipped, their
/// reasons listed in the error when none matches). @throw InputError naming the path
std::string chooseExporter(const ExporterRegistry& registry, const ExportRequest& request);

/// Writes `plan` as `request` says (unknown option keys are errors) and returns the summary:
/// {file, exporter, options, layers, vectors, build_time_s (laser plans only)}.
/// @throw InputError when no exporter fits or the chosen one cannot write this plan
nlohmann::json exportToFile(const ExporterRegistry& registry, const plan::ScanPlan& plan,
                            const ExportRequest& request);

}  // namespace vpsim::exporters
