#pragma once
/// @file
/// index.html of a run: the inputs and the answer first (job, material, cure law, machine, plan
/// summary; the verdict and the features), the cured part in 3D, every figure, the components'
/// sections, build time and stages, and the list of the files written.

#include <filesystem>
#include <string>
#include <vector>

#include "vpsim/report/job_result.h"

namespace vpsim::report {

/// Writes `outDir`/index.html. @throw InputError when it cannot be written
void writeHtmlReport(const std::string& outDir, const JobResult& result);

/// The run's files under `outDir` written at or after `since` (temporaries excluded), sorted.
std::vector<WrittenFile> filesWrittenSince(const std::string& outDir,
                                           std::filesystem::file_time_type since);

/// The figures of a run in index.html's order: (file stem or file, caption); a stem without
/// an extension has .svg and .png.
struct RunFigure {
    const char* file;
    const char* caption;
};
extern const std::vector<RunFigure> RUN_FIGURES;

}  // namespace vpsim::report
