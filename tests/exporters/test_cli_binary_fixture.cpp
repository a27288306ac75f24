// The binary CLI export byte for byte against a fixture written by hand from the format's
// specification (Common Layer Interface 2.0, as summarised in ../shared/reference/formats.md and
// read by public readers such as OpenVectorFormatTools' CliFileAccess): an ASCII header ending in
// "$$HEADEREND" with the binary data right after it, then commands, each a little-endian uint16
// command id and its parameters:
//   127 start layer long:     z                        (float32, in units)
//   130 start polyline long:  id, dir, n (int32 each), then n points x, y (float32, in units);
//                             dir 0 clockwise, 1 counter-clockwise, 2 open
//   132 start hatches long:   id, n (int32 each), then n hatches x1, y1, x2, y2 (float32)
// The coordinates are chosen so that the float32 patterns are easy to write by hand.
#include <catch2/catch.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vpsim/core/io.h"
#include "vpsim/exporters/cli_exporter.h"

using namespace vpsim;

namespace {

/// Little-endian bytes, written out as the spec lays them.
struct Bytes {
    std::string data;
    Bytes& u16(uint16_t v) {
        data += char(v & 0xff);
        data += char(v >> 8);
        return *this;
    }
    Bytes& i32(uint8_t b0, uint8_t b1, uint8_t b2, uint8_t b3) {
        data += char(b0), data += char(b1), data += char(b2), data += char(b3);
        return *this;
    }
    Bytes& i32(int v) {
        return i32(uint8_t(v), uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24));
    }
};

// IEEE 754 binary32 patterns, little-endian (sign | exponent + 127 | mantissa), by hand:
//   0    = 0x00000000
//   50   = 1.5625   x 2^5 = 0x42480000
//   100  = 1.5625   x 2^6 = 0x42C80000
//   250  = 1.953125 x 2^7 = 0x437A0000
//   400  = 1.5625   x 2^8 = 0x43C80000
//   500  = 1.953125 x 2^8 = 0x43FA0000
//   750  = 1.46484375 x 2^9 = 0x443B8000
//   1000 = 1.953125 x 2^9 = 0x447A0000
Bytes& f0(Bytes& b) {
    return b.i32(0x00, 0x00, 0x00, 0x00);
}
Bytes& f50(Bytes& b) {
    return b.i32(0x00, 0x00, 0x48, 0x42);
}
Bytes& f100(Bytes& b) {
    return b.i32(0x00, 0x00, 0xC8, 0x42);
}
Bytes& f250(Bytes& b) {
    return b.i32(0x00, 0x00, 0x7A, 0x43);
}
Bytes& f400(Bytes& b) {
    return b.i32(0x00, 0x00, 0xC8, 0x43);
}
Bytes& f500(Bytes& b) {
    return b.i32(0x00, 0x00, 0xFA, 0x43);
}
Bytes& f750(Bytes& b) {
    return b.i32(0x00, 0x80, 0x3B, 0x44);
}
Bytes& f1000(Bytes& b) {
    return b.i32(0x00, 0x00, 0x7A, 0x44);
}

std::string hex(const std::string& s, size_t from, size_t count) {
    static const char* digits = "0123456789abcdef";
    std::string out;
    for (size_t i = from; i < s.size() && i < from + count; ++i)
        out += std::string{digits[uint8_t(s[i]) >> 4], digits[uint8_t(s[i]) & 15], ' '};
    return out;
}

}  // namespace

TEST_CASE("binary CLI export matches a fixture written from the specification", "[exporters]") {
    // One layer (top at 0.05 mm) of a 1 x 0.5 mm square: its border traced counter-clockwise
    // (four chained marks that close: one polyline), then two hatches that do not chain.
    plan::ScanPlan plan;
    plan::LayerPlan layer;
    layer.z = 0.05;
    layer.vectors = {{0, 0, 1, 0, 10, 300},           {1, 0, 1, 0.5, 10, 300},
                     {1, 0.5, 0, 0.5, 10, 300},       {0, 0.5, 0, 0, 10, 300},
                     {0.25, 0.1, 0.75, 0.1, 10, 300}, {0.75, 0.4, 0.25, 0.4, 10, 300}};
    plan.layers.push_back(layer);

    // Header (ASCII; the spec fixes the commands and their order, vpsim the number format):
    // units 1 um ($$UNITS/u: u mm per coordinate unit), version 2.00 written as 200, one part
    // label, the bounding box in mm, one layer; binary data follows "$$HEADEREND" directly.
    Bytes expected;
    expected.data =
        "$$HEADERSTART\n$$BINARY\n$$UNITS/0.00100000\n$$VERSION/200\n$$LABEL/1,vpsim\n"
        "$$DIMENSION/0.000000,0.000000,0.050000,1.000000,0.500000,0.050000\n$$LAYERS/1\n"
        "$$HEADEREND";
    const size_t headerSize = expected.data.size();
    // Layer start long (127 = 0x7f 0x00), z = 0.05 mm = 50 units.
    f50(expected.u16(127));
    // Polyline long (130 = 0x82 0x00): id 1, dir 1 (counter-clockwise), 5 points, in units:
    // (0,0) (1000,0) (1000,500) (0,500) (0,0).
    expected.u16(130).i32(1).i32(1).i32(5);
    f0(f0(expected));
    f0(f1000(expected));
    f500(f1000(expected));
    f500(f0(expected));
    f0(f0(expected));
    // Hatches long (132 = 0x84 0x00): id 1, 2 hatches (x1, y1, x2, y2 each):
    // (250,100)-(750,100) and (750,400)-(250,400).
    expected.u16(132).i32(1).i32(2);
    f100(f750(f100(f250(expected))));
    f400(f250(f400(f750(expected))));
    // 2 + 4, 2 + 12 + 5 x 8, 2 + 8 + 2 x 16 bytes of geometry.
    REQUIRE(expected.data.size() == headerSize + 6 + 54 + 42);

    const std::string path =
        (std::filesystem::temp_directory_path() / "vpsim_fixture_binary.cli").string();
    exporters::CliExporter({true, 1e-3}).write(plan, path);
    const std::string written = readFile(path);
    std::filesystem::remove(path);
    size_t first = 0;
    while (first < written.size() && first < expected.data.size() &&
           written[first] == expected.data[first])
        ++first;
    INFO("first differing byte " << first << " of " << expected.data.size() << " expected, "
                                 << written.size() << " written; expected from there: "
                                 << hex(expected.data, first, 16)
                                 << "; written: " << hex(written, first, 16));
    CHECK(written.size() == expected.data.size());
    CHECK(first == expected.data.size());
}
