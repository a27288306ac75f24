#include "vpsim/core/io.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim {
namespace {

std::string temporaryName(const std::string& path) {
    return path + ".tmp." + std::to_string(::getpid());
}

/// Refuses an output path that cannot become a file before anything is written, so the user gets
/// the reason ("is a directory") instead of a rename failure.
void checkOutputPath(const std::string& path) {
    namespace fs = std::filesystem;
    if (path.empty()) throw InputError("empty output file name");
    std::error_code ec;
    if (fs::is_directory(path, ec))
        throw InputError("cannot write output: is a directory (give a file name)", path);
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw InputError(
            "cannot write output: directory " + quoteUser(parent.string()) + " does not exist",
            path);
}

std::string errnoText(int error) {
    return error == 0 ? std::string("unknown error") : std::string(std::strerror(error));
}

std::mutex& observerMutex() {
    static std::mutex mutex;
    return mutex;
}

WriteObserver& observer() {
    static WriteObserver current;
    return current;
}

void renameInto(const std::string& temporary, const std::string& path) {
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        std::filesystem::remove(temporary, ec);
        throw InputError("cannot write output: " + ec.message(), path);
    }
    std::lock_guard<std::mutex> lock(observerMutex());
    if (observer()) observer()(path);
}

}  // namespace

WriteObserver setWriteObserver(WriteObserver next) {
    std::lock_guard<std::mutex> lock(observerMutex());
    WriteObserver previous = std::move(observer());
    observer() = std::move(next);
    return previous;
}

void writeStreamAtomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
    checkOutputPath(path);
    std::string temporary = temporaryName(path);
    {
        errno = 0;
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError("cannot open for writing: " + errnoText(errno), path);
        try {
            write(out);
        } catch (...) {
            out.close();
            std::remove(temporary.c_str());
            throw;
        }
        out.flush();
        if (!out) {
            out.close();
            std::remove(temporary.c_str());
            throw InputError("write failed (disk full?)", path);
        }
    }
    renameInto(temporary, path);
}

void writeFileAtomic(const std::string& path, const std::string& contents) {
    writeStreamAtomic(path,
                      [&](std::ostream& out) { out.write(contents.data(), contents.size()); });
}

AtomicFileStream::AtomicFileStream(const std::string& path)
    : mPath(path), mTemporary(temporaryName(path)) {
    checkOutputPath(path);
    errno = 0;
    mOut = std::make_unique<std::ofstream>(mTemporary, std::ios::binary | std::ios::trunc);
    if (!*mOut) throw InputError("cannot open for writing: " + errnoText(errno), path);
}

AtomicFileStream::~AtomicFileStream() {
    if (mCommitted) return;
    mOut.reset();
    std::remove(mTemporary.c_str());
}

std::ostream& AtomicFileStream::stream() {
    return *mOut;
}

void AtomicFileStream::commit() {
    if (mCommitted) return;
    mOut->flush();
    const bool good = bool(*mOut);
    mOut->close();
    if (!good || !*mOut) {
        std::remove(mTemporary.c_str());
        mCommitted = true;
        throw InputError("write failed (disk full?)", mPath);
    }
    mCommitted = true;
    renameInto(mTemporary, mPath);
}

void writePathAtomic(const std::string& path,
                     const std::function<void(const std::string&)>& write) {
    checkOutputPath(path);
    std::string temporary = temporaryName(path);
    try {
        write(temporary);
    } catch (...) {
        std::remove(temporary.c_str());
        throw;
    }
    renameInto(temporary, path);
}

std::string readFile(const std::string& path, uint64_t maxBytes) {
    namespace fs = std::filesystem;
    if (path.empty()) throw InputError("empty file name");
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (ec || !fs::exists(status))
        throw InputError("cannot read file: " + (ec ? ec.message() : "No such file or directory"),
                         path);
    if (fs::is_directory(status)) throw InputError("is a directory, expected a file", path);
    if (!fs::is_regular_file(status))
        throw InputError("not a regular file (a device, FIFO or socket cannot be read as input)",
                         path);
    const uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > maxBytes)
        throw InputError("file is " + formatBytes(double(size)) + ", larger than the " +
                             formatBytes(double(maxBytes)) + " accepted for this input",
                         path);
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read file: " + errnoText(errno), path);
    std::string contents;
    contents.reserve(ec ? 0 : size_t(size));
    char buffer[1 << 16];
    while (in) {
        in.read(buffer, sizeof buffer);
        contents.append(buffer, size_t(in.gcount()));
        if (contents.size() > maxBytes)
            throw InputError("file grew past the " + formatBytes(double(maxBytes)) +
                                 " accepted for this input while being read",
                             path);
    }
    if (in.bad()) throw InputError("read failed: " + errnoText(errno), path);
    return contents;
}

void createDirectories(const std::string& path) {
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (ec) throw InputError("cannot create directory: " + ec.message(), path);
}

}  // namespace vpsim
