#include "batch_entries.h"

#include <cctype>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim::cli {
namespace {

bool isFolderName(const std::string& name) {
    if (name.empty() || name == "." || name == "..") return false;
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'))
            return false;
    return true;
}

void requireUniqueNames(const std::vector<BatchEntry>& entries, const std::string& file,
                        const std::string& key) {
    std::set<std::string> seen;
    for (const BatchEntry& e : entries)
        if (!seen.insert(e.name).second)
            throw InputError(
                "two jobs named " + quoteUser(e.name) + " would write the same output folder",
                file.empty() ? e.jobFile : file, key);
}

/// Throws for any key of `object` not in `allowed`.
void requireKeys(const nlohmann::json& object, const std::set<std::string>& allowed,
                 const std::string& file, const std::string& prefix) {
    std::string expected;
    for (const std::string& a : allowed) expected += (expected.empty() ? "" : ", ") + a;
    for (const auto& item : object.items())
        if (!allowed.count(item.key()))
            throw InputError("unknown key (expected one of: " + expected + ")", file,
                             prefix + item.key());
}

}  // namespace

std::vector<BatchEntry> entriesOfJobs(const std::vector<std::string>& jobFiles,
                                      const std::vector<std::string>& overrides) {
    std::vector<BatchEntry> entries;
    for (const std::string& file : jobFiles)
        entries.push_back({std::filesystem::path(file).stem().string(), file, overrides});
    requireUniqueNames(entries, "", "");
    return entries;
}

std::vector<BatchEntry> entriesOfSweep(const std::string& sweepFile,
                                       const std::vector<std::string>& overrides) {
    const nlohmann::json sweep = loadJsonFile(sweepFile);
    if (!sweep.is_object()) throw InputError("expected a JSON object", sweepFile);
    requireKeys(sweep, {"job", "runs"}, sweepFile, "");
    if (!sweep.contains("job") || !sweep["job"].is_string())
        throw InputError("expected the job file as a string", sweepFile, "job");
    if (!sweep.contains("runs") || !sweep["runs"].is_array() || sweep["runs"].empty())
        throw InputError("expected a non-empty array of runs", sweepFile, "runs");
    const std::filesystem::path job =
        std::filesystem::path(sweepFile).parent_path() / sweep["job"].get<std::string>();
    std::vector<BatchEntry> entries;
    for (size_t i = 0; i < sweep["runs"].size(); ++i) {
        const nlohmann::json& run = sweep["runs"][i];
        const std::string key = "runs[" + std::to_string(i) + "]";
        if (!run.is_object()) throw InputError("expected an object", sweepFile, key);
        requireKeys(run, {"name", "set"}, sweepFile, key + ".");
        if (!run.contains("name") || !run["name"].is_string() ||
            !isFolderName(run["name"].get<std::string>()))
            throw InputError("expected a name of letters, digits, '.', '_' or '-'", sweepFile,
                             key + ".name");
        BatchEntry entry{run["name"].get<std::string>(), job.string(), overrides};
        const nlohmann::json set = run.value("set", nlohmann::json::array());
        if (!set.is_array())
            throw InputError("expected an array of key=value", sweepFile, key + ".set");
        for (const nlohmann::json& s : set) {
            if (!s.is_string() || s.get<std::string>().find('=') == std::string::npos)
                throw InputError("expected \"key.path=value\"", sweepFile, key + ".set");
            entry.overrides.push_back(s.get<std::string>());
        }
        entries.push_back(std::move(entry));
    }
    requireUniqueNames(entries, sweepFile, "runs");
    return entries;
}

}  // namespace vpsim::cli
