#pragma once
/// @file
/// index.html: a run's numbers and pictures, every quoted text escaped.

#include <string>

#include "vpsim/report/job_result.h"

namespace vpsim::report {

/// Writes outDir/index.html from the result and the pictures already in outDir.
void writeHtmlReport(const std::string& outDir, const JobResult& result);

/// `text` with & < > " ' replaced by their HTML entities.
std::string escapeHtml(const std::string& text);

}  // namespace vpsim::report
