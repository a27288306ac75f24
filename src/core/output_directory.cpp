#include "vpsim/core/output_directory.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <memory>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/sha256.h"
#include "vpsim/core/text.h"

namespace vpsim {
namespace fs = std::filesystem;
namespace {

constexpr const char* MANIFEST_FORMAT = "vpsim-output-manifest-1";

/// "name.tmp.1234" -> 1234, or 0 when the name is not a temporary of io.cpp's form.
long temporaryPid(const std::string& name) {
    const size_t at = name.rfind(".tmp.");
    if (at == std::string::npos || at + 5 >= name.size()) return 0;
    long pid = 0;
    for (size_t i = at + 5; i < name.size(); ++i) {
        if (name[i] < '0' || name[i] > '9' || pid > 1'000'000'000) return 0;
        pid = pid * 10 + (name[i] - '0');
    }
    return pid;
}

bool processAlive(long pid) {
    if (pid == long(::getpid())) return true;
    return ::kill(pid_t(pid), 0) == 0 || errno == EPERM;
}

/// A relative name without "." or ".." parts; the manifest cannot point outside its directory.
bool safeRelativeName(const std::string& name) {
    if (name.empty() || name.size() > 1024) return false;
    const fs::path path(name);
    if (path.is_absolute()) return false;
    for (const auto& part : path)
        if (part == ".." || part == "." || part.empty()) return false;
    return true;
}

}  // namespace

std::string sha256Hex(std::string_view data) {
    Sha256 hash;
    hash.update(data.data(), data.size());
    return hash.hex();
}

std::string sha256OfFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read file to hash it", path);
    Sha256 hash;
    std::vector<char> buffer(1 << 20);
    while (in) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        hash.update(buffer.data(), size_t(in.gcount()));
    }
    if (in.bad()) throw InputError("read failed while hashing", path);
    return hash.hex();
}

size_t removeStaleTemporaries(const std::string& dir) {
    size_t removed = 0;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        const long pid = temporaryPid(it->path().filename().string());
        if (pid > 0 && !processAlive(pid) && fs::remove(it->path(), ec)) ++removed;
    }
    return removed;
}

OutputDirectory::OutputDirectory(std::string dir, nlohmann::json runInfo)
    : mDir(std::move(dir)), mRunInfo(std::move(runInfo)) {
    createDirectories(mDir);
    std::error_code ec;
    fs::remove(fs::path(mDir) / MANIFEST_NAME, ec);
    if (ec)
        throw InputError("cannot remove the previous run's manifest: " + ec.message(),
                         (fs::path(mDir) / MANIFEST_NAME).string());
    removeStaleTemporaries(mDir);
    mAbsolute = fs::absolute(mDir).lexically_normal().string();
    if (!mAbsolute.empty() && mAbsolute.back() == '/') mAbsolute.pop_back();
    mPrevious = setWriteObserver([this](const std::string& written) { noteWritten(written); });
    mObserving = true;
}

OutputDirectory::~OutputDirectory() {
    if (mObserving) setWriteObserver(mPrevious);
}

void OutputDirectory::noteWritten(const std::string& fullPath) {
    const std::string absolute = fs::absolute(fullPath).lexically_normal().string();
    if (absolute.size() <= mAbsolute.size() + 1 ||
        absolute.compare(0, mAbsolute.size(), mAbsolute) != 0 || absolute[mAbsolute.size()] != '/')
        return;  // outside the run's directory (a kernel cache, a --save elsewhere)
    const std::string name = absolute.substr(mAbsolute.size() + 1);
    if (name == MANIFEST_NAME || !safeRelativeName(name)) return;
    for (const auto& known : mNames)
        if (known == name) return;
    mNames.push_back(name);
}

std::string OutputDirectory::path(const std::string& name) const {
    if (!safeRelativeName(name) || name == MANIFEST_NAME)
        throw InputError("output file name must be relative, without '..', and not the manifest",
                         name);
    return (fs::path(mDir) / name).string();
}

void OutputDirectory::writeFile(const std::string& name, const std::string& contents) {
    const std::string full = path(name);
    createDirectories(fs::path(full).parent_path().string());
    writeFileAtomic(full, contents);
    record(name);
}

void OutputDirectory::writeStream(const std::string& name,
                                  const std::function<void(std::ostream&)>& write) {
    const std::string full = path(name);
    createDirectories(fs::path(full).parent_path().string());
    writeStreamAtomic(full, write);
    record(name);
}

void OutputDirectory::writePath(const std::string& name,
                                const std::function<void(const std::string&)>& write) {
    const std::string full = path(name);
    createDirectories(fs::path(full).parent_path().string());
    writePathAtomic(full, write);
    record(name);
}

void OutputDirectory::record(const std::string& name) {
    noteWritten(path(name));
}

void OutputDirectory::finish() {
    if (mFinished) throw Error("OutputDirectory::finish called twice for " + mDir);
    if (mObserving) {
        setWriteObserver(mPrevious);
        mObserving = false;
    }
    mEntries.clear();
    nlohmann::json files = nlohmann::json::array();
    for (const auto& name : mNames) {
        const std::string full = (fs::path(mDir) / name).string();
        std::error_code ec;
        const uintmax_t bytes = fs::file_size(full, ec);
        if (ec) continue;  // written, then removed by the run itself
        mEntries.push_back({name, uint64_t(bytes), sha256OfFile(full)});
        files.push_back(
            {{"name", name}, {"bytes", mEntries.back().bytes}, {"sha256", mEntries.back().sha256}});
    }
    const nlohmann::json manifest{
        {"format", MANIFEST_FORMAT}, {"complete", true}, {"files", files}, {"run", mRunInfo}};
    writeFileAtomic((fs::path(mDir) / MANIFEST_NAME).string(), manifest.dump(1) + "\n");
    mFinished = true;
}

namespace {

/// Parses the manifest's file list; returns "" or the reason it is unusable.
std::string readManifest(const std::string& dir, OutputVerification& out) {
    const std::string manifestPath = (fs::path(dir) / MANIFEST_NAME).string();
    std::error_code ec;
    if (!fs::exists(manifestPath, ec))
        return "no manifest.json (the run did not finish, or was interrupted)";
    nlohmann::json manifest;
    try {
        manifest = loadJsonFile(manifestPath);
    } catch (const InputError& e) {
        return "unreadable manifest: " + e.reason();
    }
    if (!manifest.is_object() || manifest.value("format", "") != MANIFEST_FORMAT ||
        manifest.value("complete", false) != true || !manifest.contains("files") ||
        !manifest["files"].is_array())
        return "manifest.json is not a complete vpsim output manifest";
    for (const auto& file : manifest["files"]) {
        if (!file.is_object() || !file.contains("name") || !file["name"].is_string() ||
            !file.contains("bytes") || !file["bytes"].is_number_unsigned() ||
            !file.contains("sha256") || !file["sha256"].is_string())
            return "manifest.json has a malformed file entry";
        ManifestEntry entry{file["name"].get<std::string>(), file["bytes"].get<uint64_t>(),
                            file["sha256"].get<std::string>()};
        if (!safeRelativeName(entry.name))
            return "manifest.json names a file outside the directory: " + quoteUser(entry.name);
        out.entries.push_back(entry);
    }
    out.runInfo = manifest.value("run", nlohmann::json::object());
    return "";
}

}  // namespace

OutputVerification verifyOutputDirectory(const std::string& dir, bool checkHashes) {
    OutputVerification out;
    out.reason = readManifest(dir, out);
    if (!out.reason.empty()) return out;
    for (const auto& entry : out.entries) {
        const std::string full = (fs::path(dir) / entry.name).string();
        std::error_code ec;
        const uintmax_t bytes = fs::file_size(full, ec);
        if (ec) {
            out.reason = quoteUser(entry.name) + " is listed in the manifest but missing";
            return out;
        }
        if (bytes != entry.bytes) {
            out.reason = quoteUser(entry.name) + ": size " + std::to_string(bytes) +
                         " differs from the manifest's " + std::to_string(entry.bytes);
            return out;
        }
        if (checkHashes) {
            std::string hash;
            try {
                hash = sha256OfFile(full);
            } catch (const InputError& e) {
                out.reason = quoteUser(entry.name) + ": " + e.reason();
                return out;
            }
            if (hash != entry.sha256) {
                out.reason =
                    quoteUser(entry.name) + ": contents differ from the manifest (SHA-256)";
                return out;
            }
        }
    }
    out.ok = true;
    return out;
}

OutputVerification requireVerifiedOutputDirectory(const std::string& dir, bool checkHashes) {
    OutputVerification out = verifyOutputDirectory(dir, checkHashes);
    if (!out.ok) throw InputError("not a complete vpsim output directory: " + out.reason, dir);
    return out;
}

}  // namespace vpsim
