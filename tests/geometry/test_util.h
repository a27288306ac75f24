#pragma once
// Helpers shared by the geometry tests: a per-process temp directory and raw STL writers for
// building broken files byte by byte.

#include <unistd.h>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "vpsim/core/error.h"
#include "vpsim/geometry/mesh.h"
#include "vpsim/geometry/test_parts.h"

namespace vpsim::test {

/// The message of the InputError that `f` throws, or "(no InputError)".
inline std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

/// A per-process temporary directory, removed when the test program exits.
class TempDir {
public:
    TempDir()
        : mPath(std::filesystem::temp_directory_path() /
                ("vpsim_geometry_test_" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(mPath);
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(mPath, ignored);
    }
    const std::filesystem::path& path() const { return mPath; }

private:
    std::filesystem::path mPath;
};

inline std::string tempPath(const std::string& name) {
    static TempDir dir;
    return (dir.path() / name).string();
}

/// Test part options with only size and height set (mm).
inline geometry::TestPartOptions sizeHeight(double size, double height) {
    geometry::TestPartOptions o;
    o.size = size;
    o.height = height;
    return o;
}

inline void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

/// Binary STL bytes of a mesh as triangle soup; `declared` overrides the header count.
inline std::string binaryStlBytes(const geometry::Mesh& mesh, int64_t declared = -1,
                                  const char* header = "test") {
    std::string out(84, '\0');
    std::memcpy(&out[0], header, std::min<size_t>(std::strlen(header), 80));
    const auto count = uint32_t(declared >= 0 ? declared : int64_t(mesh.triangles.size()));
    std::memcpy(&out[80], &count, 4);
    for (const auto& t : mesh.triangles) {
        float f[12] = {0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            for (int c = 0; c < 3; ++c) f[3 + 3 * k + c] = float(mesh.vertices[t[k]][c]);
        }
        out.append(reinterpret_cast<const char*>(f), sizeof f);
        out.append(2, '\0');
    }
    return out;
}

}  // namespace vpsim::test
