// STL reading and writing: format detection from content, round trips, every kind of broken file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "test_util.h"
#include "vpsim/core/error.h"
#include "vpsim/geometry/stl_io.h"
#include "vpsim/geometry/test_parts.h"

using namespace vpsim;
using namespace vpsim::geometry;
using Catch::Matchers::Contains;

namespace {

// Volumes of parts whose coordinates are exact in float: only double rounding in the sums.
constexpr double EXACT = 1e-12;

}  // namespace

TEST_CASE("binary STL round trip keeps the mesh exactly", "[stl]") {
    const Mesh part = makeTestPart("holes");
    const std::string path = test::tempPath("holes.stl");
    writeStl(path, part);
    MeshReport report;
    const Mesh back = readStl(path, {}, &report);
    CHECK(report.ok());
    CHECK(report.repairs.empty());
    CHECK(back.triangles.size() == part.triangles.size());
    CHECK(back.vertices.size() ==
          part.vertices.size());  // duplicates merged back to shared vertices
    CHECK(back.volume() == Approx(part.volume()).epsilon(EXACT));
    CHECK(report.volume == Approx(10.0 * 5.0 * 11.0 - 5.0 * (9.0 + 2.25)).epsilon(EXACT));
}

TEST_CASE("ASCII STL is detected from content and read", "[stl]") {
    const Mesh part = makeTestPart("l-shape");
    const std::string path = test::tempPath("l.bin");  // extension says nothing
    writeStlAscii(path, part, "my part");
    const Mesh back = readStl(path);
    CHECK(back.triangles.size() == part.triangles.size());
    CHECK(back.volume() == Approx(0.75 * 100.0 * 10.0).epsilon(EXACT));
}

TEST_CASE("binary STL whose header begins with 'solid' is read as binary", "[stl]") {
    const Mesh part = makeTestPart("box");
    const std::string path = test::tempPath("solid_header.stl");
    test::writeBytes(path, test::binaryStlBytes(part, -1, "solid exported by some CAD tool"));
    const Mesh back = readStl(path);
    CHECK(back.volume() == Approx(1000.0).epsilon(EXACT));
}

TEST_CASE("scale option converts units", "[stl]") {
    const std::string path = test::tempPath("inch.stl");
    writeStl(path, makeTestPart("box", test::sizeHeight(1.0, 1.0)));  // a 1 x 1 x 1 "inch" cube
    StlReadOptions options;
    options.scale = 25.4;
    CHECK(readStl(path, options).volume() == Approx(25.4 * 25.4 * 25.4).epsilon(EXACT));
    options.scale = -1.0;
    CHECK_THROWS_AS(readStl(path, options), InputError);
}

TEST_CASE("truncated and size-mismatched binary STL are clear errors", "[stl][bad-input]") {
    const std::string bytes = test::binaryStlBytes(makeTestPart("box"));
    const std::string path = test::tempPath("broken.stl");

    test::writeBytes(path, bytes.substr(0, bytes.size() - 30));
    CHECK_THAT(test::messageOf([&] { readStl(path); }), Contains("broken.stl") &&
                                                            Contains("truncated binary STL") &&
                                                            Contains("12 triangles"));

    // A binary file whose header starts with "solid" is still recognised as a truncated binary.
    const std::string solidHeader = test::binaryStlBytes(makeTestPart("box"), -1, "solid from CAD");
    test::writeBytes(path, solidHeader.substr(0, solidHeader.size() - 50));
    CHECK_THAT(test::messageOf([&] { readStl(path); }), Contains("truncated binary STL"));

    test::writeBytes(path, bytes + std::string(50, '\0'));
    CHECK_THAT(test::messageOf([&] { readStl(path); }), Contains("disagrees with the file size"));

    test::writeBytes(path, bytes.substr(0, 40));
    CHECK_THAT(test::messageOf([&] { readStl(path); }), Contains("84-byte"));

    test::writeBytes(path, "");
    CHECK_THAT(test::messageOf([&] { readStl(path); }), Contains("truncated"));

    CHECK_THAT(test::messageOf([&] { readStl(test::tempPath("missing.stl")); }),
               Contains("missing.stl"));
}

TEST_CASE("NaN and infinite coordinates are rejected with the triangle number",
          "[stl][bad-input]") {
    Mesh soup = makeTestPart("box");
    const uint32_t bad = soup.triangles[3][1];
    soup.vertices[bad].y = std::numeric_limits<double>::quiet_NaN();
    size_t first = 0;  // the first triangle using that vertex, 1-based in the message
    while (std::count(soup.triangles[first].begin(), soup.triangles[first].end(), bad) == 0)
        ++first;
    const std::string path = test::tempPath("nan.stl");
    test::writeBytes(path, test::binaryStlBytes(soup));
    CHECK_THAT(
        test::messageOf([&] { readStl(path); }),
        Contains("triangle " + std::to_string(first + 1) + " has") && Contains("non-finite"));

    test::writeBytes(path,
                     "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 inf\n"
                     "vertex 0 1 0\nendloop\nendfacet\nendsolid x\n");
    CHECK_THAT(test::messageOf([&] { readStl(path); }),
               Contains("nan.stl:3") && Contains("non-finite"));
}

TEST_CASE("malformed ASCII STL names the line", "[stl][bad-input]") {
    const std::string path = test::tempPath("bad_ascii.stl");
    test::writeBytes(path,
                     "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 zero 0\n");
    CHECK_THAT(test::messageOf([&] { readStl(path); }),
               Contains("bad_ascii.stl:5") && Contains("expected a number"));
    test::writeBytes(path, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n");
    CHECK_THAT(test::messageOf([&] { readStl(path); }), Contains("end of file"));
    test::writeBytes(path, "solid x\nendsolid x\n");
    CHECK_THAT(test::messageOf([&] { readStl(path); }), Contains("no triangles"));
}

TEST_CASE("bundled example parts read cleanly with their documented volumes", "[stl]") {
    const std::string dir = std::string(VPSIM_SOURCE_DIR) + "/examples/parts/";
    const std::vector<std::pair<std::string, double>> parts{{"holes", 493.75},
                                                            {"overhangs", 320.0},
                                                            {"l-shape", 750.0},
                                                            {"tapered", 1750.0 / 3.0},
                                                            {"bottom-narrow", 1750.0 / 3.0},
                                                            {"pillars", 8.0}};
    for (const auto& [name, volume] : parts) {
        MeshReport report;
        const Mesh mesh = readStl(dir + name + ".stl", {}, &report);
        INFO(name);
        CHECK(report.ok());
        CHECK(report.repairs.empty());
        CHECK(mesh.volume() == Approx(volume).epsilon(EXACT));
    }
    // Cylinder coordinates are cos/sin rounded to float: relative 1e-6.
    CHECK(readStl(dir + "cylinder.stl").volume() == Approx(784.137).epsilon(1e-6));
}
