#include "vpsim/core/io.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "vpsim/core/error.h"

namespace vpsim {
namespace {

std::string temporaryName(const std::string& path) {
    return path + ".tmp." + std::to_string(::getpid());
}

void renameInto(const std::string& temporary, const std::string& path) {
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        std::filesystem::remove(temporary, ec);
        throw InputError("cannot write output: " + ec.message(), path);
    }
}

}  // namespace

void writeStreamAtomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
    std::string temporary = temporaryName(path);
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out)
            throw InputError(std::string("cannot open for writing: ") + std::strerror(errno), path);
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

void writePathAtomic(const std::string& path,
                     const std::function<void(const std::string&)>& write) {
    std::string temporary = temporaryName(path);
    try {
        write(temporary);
    } catch (...) {
        std::remove(temporary.c_str());
        throw;
    }
    renameInto(temporary, path);
}

std::string readFile(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError("is a directory, expected a file", path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(std::string("cannot read file: ") + std::strerror(errno), path);
    std::ostringstream contents;
    contents << in.rdbuf();
    return contents.str();
}

void createDirectories(const std::string& path) {
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (ec) throw InputError("cannot create directory: " + ec.message(), path);
}

}  // namespace vpsim
