#pragma once
/// @file
/// Output files are written to a temporary name beside the target and renamed when complete,
/// so a failure never leaves a truncated or corrupted output behind.

#include <functional>
#include <iosfwd>
#include <string>

namespace vpsim {

/// Writes `contents` to `path` atomically. @throw InputError when the file cannot be written.
void writeFileAtomic(const std::string& path, const std::string& contents);
/// Calls write(stream) on a temporary file, then renames it to `path`. If write throws, the
/// temporary is removed and the exception propagates. Binary mode.
void writeStreamAtomic(const std::string& path, const std::function<void(std::ostream&)>& write);
/// Calls write(tempPath) for libraries that write files themselves (OpenVDB, libpng), then
/// renames tempPath to `path`.
void writePathAtomic(const std::string& path, const std::function<void(const std::string&)>& write);
/// Reads a whole file. @throw InputError naming the file when it cannot be read.
std::string readFile(const std::string& path);
/// Creates a directory and its parents. @throw InputError when that fails.
void createDirectories(const std::string& path);

}  // namespace vpsim
