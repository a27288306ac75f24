#include "vpsim/geometry/stl_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <ostream>
#include <sstream>
#include <string_view>

#include <glm/geometric.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/log.h"
#include "vpsim/core/text.h"

namespace vpsim::geometry {
namespace {

constexpr size_t HEADER_BYTES = 84;  // 80-byte header + uint32 triangle count
constexpr size_t TRIANGLE_BYTES = 50;
constexpr double MAX_COORDINATE = 1e7;  // mm  // normal + 3 vertices (12 floats) + uint16 attribute

void checkFinite(const Mesh& soup, size_t triangle, const std::string& path, int line) {
    for (int k = 0; k < 3; ++k) {
        const glm::dvec3& v = soup.vertices[3 * triangle + k];
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
            std::ostringstream s;
            s << "triangle " << triangle + 1 << " has a non-finite coordinate (" << v.x << ", "
              << v.y << ", " << v.z << ")";
            throw InputError(s.str(), path, "", line);
        }
        // 10 km: beyond it the file is not in mm (or is garbage), and volumes would overflow.
        if (std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}) > MAX_COORDINATE) {
            std::ostringstream s;
            s << "triangle " << triangle + 1 << " has a coordinate beyond +-1e7 mm (" << v.x << ", "
              << v.y << ", " << v.z << "): is the file in mm?";
            throw InputError(s.str(), path, "", line);
        }
    }
}

void addTriangle(Mesh& soup) {
    const auto base = static_cast<uint32_t>(soup.vertices.size() - 3);
    soup.triangles.push_back({base, base + 1, base + 2});
}

Mesh parseBinary(const std::string& data, const std::string& path, double scale) {
    uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    Mesh soup;
    soup.vertices.reserve(size_t(count) * 3);
    soup.triangles.reserve(count);
    const char* p = data.data() + HEADER_BYTES;
    for (uint32_t t = 0; t < count; ++t, p += TRIANGLE_BYTES) {
        float f[9];
        std::memcpy(f, p + 12,
                    sizeof f);  // skip the stored normal: it is recomputed, never trusted
        for (int k = 0; k < 3; ++k) {
            soup.vertices.emplace_back(double(f[3 * k]) * scale, double(f[3 * k + 1]) * scale,
                                       double(f[3 * k + 2]) * scale);
        }
        addTriangle(soup);
        checkFinite(soup, t, path, 0);
    }
    return soup;
}

/// Separators in an ASCII STL: whitespace, and NUL bytes, which some exporters pad files with.
bool isSeparator(char c) {
    return c == '\0' || std::isspace(static_cast<unsigned char>(c));
}

/// Keywords compare case-insensitively: admesh and others write "SOLID", "FACET NORMAL".
bool sameWord(std::string_view token, std::string_view word) {
    if (token.size() != word.size()) return false;
    for (size_t i = 0; i < token.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(token[i])) != word[i]) return false;
    return true;
}

constexpr std::string_view UTF8_BOM = "\xEF\xBB\xBF";

/// Whitespace tokenizer over an ASCII STL that tracks line numbers for messages.
class AsciiReader {
public:
    AsciiReader(const std::string& data, const std::string& path) : mData(data), mPath(path) {
        if (std::string_view(mData).substr(0, UTF8_BOM.size()) == UTF8_BOM) mPos = UTF8_BOM.size();
    }

    bool atEnd() {
        skipSpace();
        return mPos >= mData.size();
    }
    /// The next whitespace-separated token (a view into the file: no allocation per token).
    std::string_view token() {
        skipSpace();
        const size_t start = mPos;
        while (mPos < mData.size() && !isSeparator(mData[mPos])) ++mPos;
        return std::string_view(mData).substr(start, mPos - start);
    }
    void expect(const char* word) {
        const std::string_view t = token();
        if (!sameWord(t, word)) fail(std::string("expected '") + word + "', found " + describe(t));
    }
    double number() {
        const std::string_view t = token();
        const std::optional<double> v = parseDecimal(t);
        if (v) return *v;
        // inf and nan are numbers some exporters write: the finite check names the triangle.
        const std::string word = asciiLower(t.substr(t.size() > 0 && (t[0] == '-' || t[0] == '+')));
        if (word == "inf" || word == "infinity") return HUGE_VAL;
        if (word == "nan") return std::nan("");
        fail("expected a number, found " + describe(t));
    }
    /// Skips the solid's name: the rest of the line, or up to the first facet when a whole file
    /// is written on one line.
    void skipName() {
        while (mPos < mData.size() && mData[mPos] != '\n') {
            while (mPos < mData.size() && mData[mPos] != '\n' && isSeparator(mData[mPos])) ++mPos;
            size_t end = mPos;
            while (end < mData.size() && !isSeparator(mData[end])) ++end;
            const std::string_view word = std::string_view(mData).substr(mPos, end - mPos);
            if (sameWord(word, "facet") || sameWord(word, "endsolid")) return;
            mPos = end;
        }
    }
    void skipLine() {
        while (mPos < mData.size() && mData[mPos] != '\n') ++mPos;
    }
    int line() const { return mLine; }
    [[noreturn]] void fail(const std::string& reason) const {
        throw InputError(reason, mPath, "", mLine);
    }

private:
    static std::string describe(std::string_view t) {
        return t.empty() ? std::string("end of file (truncated?)") : quoteUser(t, 40);
    }
    void skipSpace() {
        while (mPos < mData.size() && isSeparator(mData[mPos])) {
            if (mData[mPos] == '\n') ++mLine;
            ++mPos;
        }
    }
    const std::string& mData;
    const std::string& mPath;
    size_t mPos = 0;
    int mLine = 1;
};

Mesh parseAscii(const std::string& data, const std::string& path, double scale) {
    AsciiReader in(data, path);
    Mesh soup;
    while (!in.atEnd()) {
        in.expect("solid");
        in.skipName();
        for (;;) {
            const std::string_view word = in.token();
            if (sameWord(word, "endsolid")) {
                in.skipLine();
                break;
            }
            if (!sameWord(word, "facet")) {
                in.fail(
                    "expected 'facet' or 'endsolid', found " +
                    (word.empty() ? std::string("end of file (truncated?)") : quoteUser(word, 40)));
            }
            in.expect("normal");
            for (int k = 0; k < 3; ++k) in.number();  // stored normals are ignored
            in.expect("outer");
            in.expect("loop");
            const int facetLine = in.line();
            for (int k = 0; k < 3; ++k) {
                in.expect("vertex");
                const double x = in.number(), y = in.number(), z = in.number();
                soup.vertices.emplace_back(x * scale, y * scale, z * scale);
            }
            in.expect("endloop");
            in.expect("endfacet");
            addTriangle(soup);
            checkFinite(soup, soup.triangles.size() - 1, path, facetLine);
        }
    }
    return soup;
}

/// An ASCII STL starts (after a BOM and space) with "solid", a name line, then "facet" or
/// "endsolid". Binary headers often begin with "solid" too, but are not followed by a facet.
bool looksLikeAscii(const std::string& data) {
    std::string_view view(data);
    if (view.substr(0, UTF8_BOM.size()) == UTF8_BOM) view.remove_prefix(UTF8_BOM.size());
    size_t i = 0;
    while (i < view.size() && isSeparator(view[i])) ++i;
    if (!sameWord(view.substr(i, 5), "solid")) return false;
    const size_t lineEnd = view.find('\n', i);
    if (lineEnd == std::string_view::npos)  // all on one line
        return asciiLower(view.substr(0, 4096)).find("facet normal") != std::string::npos;
    i = lineEnd + 1;
    while (i < view.size() && isSeparator(view[i])) ++i;
    size_t end = i;
    while (end < view.size() && !isSeparator(view[end])) ++end;
    const std::string_view word = view.substr(i, end - i);
    return sameWord(word, "facet") || sameWord(word, "endsolid");
}

}  // namespace

Mesh readStlSoup(const std::string& path, double scale) {
    if (!(scale > 0.0) || !std::isfinite(scale)) {
        throw InputError("STL scale must be a positive number, got " + formatQuantity(scale), path);
    }
    return parseStlSoup(readFile(path), path, scale);
}

Mesh parseStlSoup(const std::string& data, const std::string& path, double scale) {
    if (!(scale > 0.0) || !std::isfinite(scale)) {
        throw InputError("STL scale must be a positive number, got " + formatQuantity(scale), path);
    }
    Mesh soup;
    uint32_t count = 0;
    if (data.size() >= HEADER_BYTES) std::memcpy(&count, data.data() + 80, 4);
    const uint64_t expected = HEADER_BYTES + uint64_t(count) * TRIANGLE_BYTES;
    if (data.size() >= HEADER_BYTES && data.size() == expected) {
        soup = parseBinary(data, path, scale);
    } else if (looksLikeAscii(data)) {
        try {
            soup = parseAscii(data, path, scale);
        } catch (const InputError& e) {
            if (data.size() < HEADER_BYTES) throw;
            // Binary files often start with "solid" too: say what the binary reading would be.
            throw InputError(
                e.reason() +
                    " (read as ASCII because it starts with 'solid'; as a binary STL its "
                    "header declares " +
                    std::to_string(count) + " triangles = " + std::to_string(expected) +
                    " bytes, but the file has " + std::to_string(data.size()) + ")",
                path, "", e.line());
        }
    } else if (data.size() < HEADER_BYTES) {
        throw InputError("truncated STL: " + std::to_string(data.size()) +
                             " bytes, not ASCII and shorter than the 84-byte binary header",
                         path);
    } else if (data.size() < expected) {
        throw InputError("truncated binary STL: the header declares " + std::to_string(count) +
                             " triangles (" + std::to_string(expected) +
                             " bytes) but the file has " + std::to_string(data.size()) + " bytes",
                         path);
    } else {
        throw InputError(
            "binary STL triangle count disagrees with the file size: the header declares " +
                std::to_string(count) + " triangles (" + std::to_string(expected) +
                " bytes) but the file has " + std::to_string(data.size()) + " bytes",
            path);
    }
    if (soup.triangles.empty()) throw InputError("STL file contains no triangles", path);
    return soup;
}

Mesh readStl(const std::string& path, const StlReadOptions& options, MeshReport* report) {
    Mesh mesh = readStlSoup(path, options.scale);
    MeshReport r = checkMesh(mesh, path, options.check);
    if (report) *report = std::move(r);
    return mesh;
}

namespace {

std::string binaryStl(const Mesh& mesh, const std::string& solidName) {
    std::string out(HEADER_BYTES + mesh.triangles.size() * TRIANGLE_BYTES, '\0');
    std::string header = "vpsim binary STL, mm: " + solidName;  // never begins with "solid"
    std::memcpy(&out[0], header.data(), std::min<size_t>(header.size(), 80));
    const auto count = static_cast<uint32_t>(mesh.triangles.size());
    std::memcpy(&out[80], &count, 4);
    char* p = &out[HEADER_BYTES];
    for (size_t t = 0; t < mesh.triangles.size(); ++t, p += TRIANGLE_BYTES) {
        const glm::dvec3 n = mesh.triangleNormal(t);
        const double len = glm::length(n);
        const glm::dvec3 unit = len > 0.0 ? n / len : glm::dvec3(0.0);
        float f[12] = {float(unit.x), float(unit.y), float(unit.z)};
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3& v = mesh.vertices[mesh.triangles[t][k]];
            f[3 + 3 * k] = float(v.x);
            f[4 + 3 * k] = float(v.y);
            f[5 + 3 * k] = float(v.z);
        }
        std::memcpy(p, f, sizeof f);
    }
    return out;
}

}  // namespace

void writeStl(const std::string& path, const Mesh& mesh, const std::string& solidName) {
    if (mesh.triangles.size() > UINT32_MAX)
        throw InputError("too many triangles for a binary STL", path);
    writeFileAtomic(path, binaryStl(mesh, solidName));
}

void writeStlAscii(const std::string& path, const Mesh& mesh, const std::string& solidName) {
    writeStreamAtomic(path, [&](std::ostream& os) {
        os.precision(9);
        os << "solid " << solidName << "\n";
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::dvec3 n = mesh.triangleNormal(t);
            const double len = glm::length(n);
            const glm::dvec3 u = len > 0.0 ? n / len : glm::dvec3(0.0);
            os << "  facet normal " << u.x << " " << u.y << " " << u.z << "\n    outer loop\n";
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3& v = mesh.vertices[mesh.triangles[t][k]];
                os << "      vertex " << float(v.x) << " " << float(v.y) << " " << float(v.z)
                   << "\n";
            }
            os << "    endloop\n  endfacet\n";
        }
        os << "endsolid " << solidName << "\n";
    });
}

Mesh readStl(const std::string& path, double scale) {
    StlReadOptions options;
    options.scale = scale;
    return readStl(path, options);
}

}  // namespace vpsim::geometry
