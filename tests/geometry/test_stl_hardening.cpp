// Real-world ASCII STL variants (upper-case keywords as admesh writes them, a UTF-8 BOM, NUL
// padding), messages that quote binary bytes, and tall thin parts that are not "flat".
#include <catch2/catch.hpp>

#include <cctype>

#include "test_util.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/geometry/mesh_check.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/geometry/test_parts.h"

using namespace vpsim;
using namespace vpsim::geometry;
using Catch::Matchers::Contains;

namespace {

std::string asciiBox() {
    const std::string path = test::tempPath("ascii_box.stl");
    writeStlAscii(path, makeTestPart("box"), "block");
    return readFile(path);
}

std::string upper(std::string text) {
    for (char& c : text) c = char(std::toupper(static_cast<unsigned char>(c)));
    return text;
}

double volumeOf(const std::string& name, const std::string& bytes) {
    const std::string path = test::tempPath(name);
    test::writeBytes(path, bytes);
    return readStl(path).volume();
}

}  // namespace

TEST_CASE("ASCII STL keywords are case-insensitive (admesh writes SOLID, FACET)", "[stl]") {
    const double volume = makeTestPart("box").volume();
    CHECK(volumeOf("upper.stl", upper(asciiBox())) == Approx(volume));
    std::string mixed = asciiBox();
    mixed.replace(mixed.find("facet normal"), 12, "Facet Normal");
    CHECK(volumeOf("mixed.stl", mixed) == Approx(volume));
}

TEST_CASE("ASCII STL with a UTF-8 BOM or NUL bytes is read, not called a binary", "[stl]") {
    const double volume = makeTestPart("box").volume();
    CHECK(volumeOf("bom.stl", "\xEF\xBB\xBF" + asciiBox()) == Approx(volume));
    CHECK(volumeOf("nul_padded.stl", asciiBox() + std::string(300, '\0')) == Approx(volume));
    std::string nulSeparated = asciiBox();
    nulSeparated[nulSeparated.find(' ', nulSeparated.find("vertex"))] = '\0';
    CHECK(volumeOf("nul_inside.stl", nulSeparated) == Approx(volume));
    std::string oneLine = asciiBox();
    for (char& c : oneLine)
        if (c == '\n') c = ' ';
    CHECK(volumeOf("one_line.stl", oneLine) == Approx(volume));
}

TEST_CASE("STL errors quoting file bytes stay one printable line", "[stl]") {
    std::string broken = asciiBox();
    broken.replace(broken.find("vertex"), 6, "ver\x01\x1b[2J\xff");
    const std::string path = test::tempPath("binary_bytes.stl");
    test::writeBytes(path, broken);
    const std::string message = test::messageOf([&] { readStl(path); });
    CHECK_THAT(message, Contains("expected 'vertex'") && Contains("\\x01"));
    for (unsigned char c : message) CHECK((c >= 0x20 && c != 0x7F));
    std::string hex = asciiBox();
    hex.replace(hex.find("vertex ") + 7, 1, "0x1");
    test::writeBytes(path, hex);
    CHECK_THAT(test::messageOf([&] { readStl(path); }), Contains("expected a number"));
}

TEST_CASE("a 1 x 1 x 1e6 mm column encloses volume; a flat sheet does not", "[mesh]") {
    const Mesh column = makeTestPart("box", test::sizeHeight(1.0, 1e6));
    Mesh copy = column;
    const MeshReport report = checkMesh(copy, "column", {});
    CHECK(report.ok());
    CHECK(report.volume == Approx(1e6));
    Mesh thin = makeTestPart("box", test::sizeHeight(100.0, 1e-3));
    CHECK(checkMesh(thin, "plate", {}).ok());
    // Squash a box to zero height: every triangle stays, the volume goes.
    Mesh flat = makeTestPart("box");
    for (auto& v : flat.vertices) v.z = 0.0;
    MeshCheckOptions keep;
    keep.throwOnProblem = false;
    const MeshReport flatReport = checkMesh(flat, "flat", keep);
    CHECK_FALSE(flatReport.ok());
}
