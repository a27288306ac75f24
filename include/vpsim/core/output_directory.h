#pragma once
/// @file
/// Output directories that are never misleading. A run opens its directory with OutputDirectory
/// (which first removes the previous manifest and stale temporaries of killed runs), writes each
/// file atomically through it, and finish() writes manifest.json last, listing every file with
/// its size and SHA-256. A reader trusts a directory only when verifyOutputDirectory() says the
/// manifest matches, so an interrupted run leaves either the previous complete set (if it was
/// killed before begin) or a directory without a manifest, never a mix that looks complete.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace vpsim {

/// File name of the manifest inside an output directory.
constexpr const char* MANIFEST_NAME = "manifest.json";

/// SHA-256 of bytes, as 64 lower-case hex digits.
std::string sha256Hex(std::string_view data);
/// SHA-256 of a file's contents, read in chunks. @throw InputError when it cannot be read.
std::string sha256OfFile(const std::string& path);

/// One file of a run, named relative to its output directory ("kernel/table.vdb").
struct ManifestEntry {
    std::string name;
    uint64_t bytes = 0;
    std::string sha256;
};

/// Writer of one run's output directory. While it exists, every file completed by the atomic
/// writers of io.h inside the directory is recorded (see setWriteObserver), so code that writes
/// with writeStl, writePng, saveScanPlan ... needs no change: open an OutputDirectory at the start
/// of the run and call finish() at the end.
class OutputDirectory {
public:
    /// Begins a run in `dir`: creates it, removes manifest.json and every `*.tmp.PID` temporary
    /// whose process is gone, and starts recording writes under it. Files of the previous run
    /// stay until replaced but are no longer trusted.
    /// @throw InputError when the directory cannot be created or cleaned.
    explicit OutputDirectory(std::string dir, nlohmann::json runInfo = nlohmann::json::object());
    ~OutputDirectory();
    OutputDirectory(const OutputDirectory&) = delete;
    OutputDirectory& operator=(const OutputDirectory&) = delete;

    const std::string& directory() const { return mDir; }
    /// Full path of a file of the run. @throw InputError on an absolute name or one with "..".
    std::string path(const std::string& name) const;

    /// Writes a file atomically (temporary + rename) and records it; creates parent folders.
    void writeFile(const std::string& name, const std::string& contents);
    void writeStream(const std::string& name, const std::function<void(std::ostream&)>& write);
    /// For libraries that write files themselves (OpenVDB, libpng): write(temporaryPath).
    void writePath(const std::string& name, const std::function<void(const std::string&)>& write);
    /// Records a file written inside the directory by code that bypasses io.h's writers.
    void record(const std::string& name);

    /// Stops recording, hashes every recorded file that still exists and writes manifest.json
    /// (atomically, last). Call once, after every file of the run. @throw InputError on failure.
    void finish();
    /// The manifest's entries (filled by finish()).
    const std::vector<ManifestEntry>& entries() const { return mEntries; }

private:
    void noteWritten(const std::string& fullPath);
    std::string mDir;
    std::string mAbsolute;  ///< normalised absolute directory, to match written paths
    nlohmann::json mRunInfo;
    std::vector<std::string> mNames;  ///< recorded files, in first-write order
    std::vector<ManifestEntry> mEntries;
    std::function<void(const std::string&)> mPrevious;  ///< observer restored on finish
    bool mFinished = false, mObserving = false;
};

/// Outcome of checking an output directory against its manifest.
struct OutputVerification {
    bool ok = false;
    std::string reason;  ///< why not, e.g. "plan.json: size 120 differs from the manifest's 4096"
    std::vector<ManifestEntry> entries;
    nlohmann::json runInfo;
};

/// Checks that `dir` has a manifest and that every file it lists exists with the listed size
/// and (when checkHashes) SHA-256. Never throws for a bad directory: the reason says what is wrong.
OutputVerification verifyOutputDirectory(const std::string& dir, bool checkHashes = true);
/// verifyOutputDirectory or @throw InputError naming the directory and the reason.
OutputVerification requireVerifiedOutputDirectory(const std::string& dir, bool checkHashes = true);

/// Removes `*.tmp.PID` files under `dir` whose process no longer runs; returns how many.
size_t removeStaleTemporaries(const std::string& dir);

}  // namespace vpsim
