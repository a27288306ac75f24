#pragma once
/// @file
/// Output files are written to a temporary name beside the target and renamed when complete,
/// so a failure never leaves a truncated or corrupted output behind.

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>

namespace vpsim {

/// Writes `contents` to `path` atomically. @throw InputError when the file cannot be written
/// (the message says why: a directory of that name, a missing parent, no permission, disk full).
void writeFileAtomic(const std::string& path, const std::string& contents);
/// Calls write(stream) on a temporary file, then renames it to `path`. If write throws, the
/// temporary is removed and the exception propagates. Binary mode.
void writeStreamAtomic(const std::string& path, const std::function<void(std::ostream&)>& write);
/// Calls write(tempPath) for libraries that write files themselves (OpenVDB, libpng), then
/// renames tempPath to `path`.
void writePathAtomic(const std::string& path, const std::function<void(const std::string&)>& write);
/// A file written as a stream over a long computation (a mesh as it is produced): opened under a
/// temporary name beside `path`, renamed to `path` by commit(); removed if never committed.
class AtomicFileStream {
public:
    /// @throw InputError when the temporary cannot be opened (the message says why)
    explicit AtomicFileStream(const std::string& path);
    ~AtomicFileStream();
    AtomicFileStream(const AtomicFileStream&) = delete;
    AtomicFileStream& operator=(const AtomicFileStream&) = delete;
    std::ostream& stream();
    const std::string& path() const { return mPath; }
    /// Flushes, checks and renames. @throw InputError when a write failed (disk full?)
    void commit();

private:
    std::string mPath, mTemporary;
    std::unique_ptr<std::ofstream> mOut;
    bool mCommitted = false;
};

/// Told the final path of every file the atomic writers above complete (after the rename).
using WriteObserver = std::function<void(const std::string& path)>;
/// Installs the process-wide observer (an empty function removes it); returns the previous one.
/// OutputDirectory uses it to list a run's files without every writer knowing about manifests.
WriteObserver setWriteObserver(WriteObserver observer);

/// Largest input file read by default (STL parts, JSON jobs, CSV): 2 GiB.
constexpr uint64_t DEFAULT_READ_LIMIT = uint64_t(2) << 30;
/// Reads a whole regular file of at most `maxBytes`. Devices, FIFOs and directories are refused
/// (`/dev/zero` would never end), and the read itself stops at the limit in case the file grows.
/// @throw InputError naming the file when it cannot be read, is not a regular file or is larger
///        than `maxBytes`
std::string readFile(const std::string& path, uint64_t maxBytes = DEFAULT_READ_LIMIT);
/// Creates a directory and its parents. @throw InputError when that fails.
void createDirectories(const std::string& path);

}  // namespace vpsim
