#pragma once
// Private to the report module: index.html showing a run's numbers and pictures.
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace vpsim::report {

/// Writes outDir/index.html from the report and the pictures already in outDir.
void writeHtmlReport(const std::string& outDir, const nlohmann::json& report);

}  // namespace vpsim::report
