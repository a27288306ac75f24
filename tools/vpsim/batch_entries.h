#pragma once
// The jobs of `vpsim batch`: job files as given, or a sweep file (one job and a list of --set
// overrides), each with the name of its output folder.
#include <string>
#include <vector>

namespace vpsim::cli {

struct BatchEntry {
    std::string name;                    ///< output folder DIR/<name>, unique in the batch
    std::string jobFile;                 ///< the job file
    std::vector<std::string> overrides;  ///< --set given on the command line, then the entry's
};

/// One entry per job file, named by the file's stem. @throw InputError for two jobs of one name
std::vector<BatchEntry> entriesOfJobs(const std::vector<std::string>& jobFiles,
                                      const std::vector<std::string>& overrides);

/// The runs of a sweep file:
///   {"job": "default.json", "runs": [{"name": "dose-10", "set": ["cure.critical_dose=10"]}, ...]}
/// "job" relative to the sweep file's folder; names of letters, digits, '.', '_' and '-'.
/// @throw InputError naming the file and key (unknown keys, missing or mistyped values, a bad
///        or repeated name)
std::vector<BatchEntry> entriesOfSweep(const std::string& sweepFile,
                                       const std::vector<std::string>& overrides);

}  // namespace vpsim::cli
