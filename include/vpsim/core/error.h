#pragma once
/// @file
/// The one exception hierarchy of vpsim. The CLI turns each into a single clear line and a
/// non-zero exit code; library code throws, it never prints and exits.

#include <stdexcept>
#include <string>

namespace vpsim {

/// Base of every vpsim error. what() is the complete one-line message shown to the user.
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Bad user input: a malformed file, an unknown or wrong-typed config key, an impossible value.
/// The message names the file (and line or key where known) and the reason.
class InputError : public Error {
public:
    /// @param reason what is wrong, e.g. "expected a length, got '10 mW'"
    /// @param file   file the input came from ("" when it came from the command line)
    /// @param key    config key path such as "particles.radius" ("" when not applicable)
    /// @param line   1-based line number, 0 when unknown
    InputError(const std::string& reason, const std::string& file = "", const std::string& key = "",
               int line = 0);
    const std::string& file() const { return mFile; }
    const std::string& key() const { return mKey; }
    const std::string& reason() const { return mReason; }
    int line() const { return mLine; }

private:
    std::string mReason, mFile, mKey;
    int mLine = 0;
};

/// A Vulkan call failed or no usable device exists. Carries the VkResult name and the source
/// location of the failing call.
class GpuError : public Error {
public:
    GpuError(const std::string& what, const std::string& resultName, const char* file, int line);
    explicit GpuError(const std::string& what) : Error("GPU: " + what) {}
    const std::string& resultName() const { return mResultName; }

private:
    std::string mResultName;
};

/// A request that would exceed memory, device limits or a sane size; refused before allocating.
class ResourceError : public Error {
public:
    explicit ResourceError(const std::string& message) : Error(message) {}
};

/// Formats a byte count for messages ("1.50 GiB").
std::string formatBytes(double bytes);

}  // namespace vpsim
