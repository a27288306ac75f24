// Reads CLI files back (ASCII and binary, see cli_exporter.h): used by the round-trip test and by
// anyone checking a written scan.cli.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/exporters/cli_exporter.h"

namespace vpsim::exporters {
namespace {

std::string trim(const std::string& s) {
    size_t a = s.find_first_not_of(" \t\r\n"), b = s.find_last_not_of(" \t\r\n");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::vector<double> numbers(const std::string& text, const std::string& path) {
    std::vector<double> out;
    std::string token;
    std::stringstream in(text);
    while (std::getline(in, token, ',')) {
        token = trim(token);
        if (token.empty()) continue;
        char* end = nullptr;
        double v = std::strtod(token.c_str(), &end);
        if (end == token.c_str() || *end != '\0')
            throw InputError("CLI: '" + token + "' is not a number", path);
        out.push_back(v);
    }
    return out;
}

class BinaryCursor {
public:
    BinaryCursor(const std::string& data, size_t pos, const std::string& path)
        : mData(data), mPos(pos), mPath(path) {}
    bool done() const { return mPos >= mData.size(); }
    uint16_t u16() { return uint16_t(byte(0) | byte(1) << 8) + skip(2); }
    int32_t i32() {
        uint32_t v = uint32_t(byte(0)) | uint32_t(byte(1)) << 8 | uint32_t(byte(2)) << 16 |
                     uint32_t(byte(3)) << 24;
        skip(4);
        int32_t out;
        std::memcpy(&out, &v, 4);
        return out;
    }
    double f32() {
        int32_t bits = i32();
        float f;
        std::memcpy(&f, &bits, 4);
        return double(f);
    }

private:
    uint32_t byte(size_t k) const {
        if (mPos + k >= mData.size()) throw InputError("CLI: binary geometry ends early", mPath);
        return uint8_t(mData[mPos + k]);
    }
    uint16_t skip(size_t n) {
        mPos += n;
        return 0;
    }
    const std::string& mData;
    size_t mPos;
    const std::string& mPath;
};

CliLayer& currentLayer(CliFile& file, const std::string& path) {
    if (file.layers.empty()) throw InputError("CLI: geometry before the first layer", path);
    return file.layers.back();
}

void readBinary(CliFile& file, const std::string& data, size_t pos, const std::string& path) {
    BinaryCursor in(data, pos, path);
    const double u = file.units;
    while (!in.done()) {
        const uint16_t command = in.u16();
        if (command == 127 || command == 128) {
            file.layers.push_back({});
            file.layers.back().z = (command == 127 ? in.f32() : double(in.u16())) * u;
        } else if (command == 129 || command == 130) {
            const bool isLong = command == 130;
            CliPolyline line;
            line.id = isLong ? in.i32() : in.u16();
            line.direction = isLong ? in.i32() : in.u16();
            const long n = isLong ? in.i32() : in.u16();
            if (n < 0) throw InputError("CLI: negative polyline size", path);
            for (long k = 0; k < n; ++k) {
                double x = isLong ? in.f32() : in.u16(), y = isLong ? in.f32() : in.u16();
                line.points.push_back({x * u, y * u});
            }
            currentLayer(file, path).polylines.push_back(std::move(line));
        } else if (command == 131 || command == 132) {
            const bool isLong = command == 132;
            CliHatches hatches;
            hatches.id = isLong ? in.i32() : in.u16();
            const long n = isLong ? in.i32() : in.u16();
            if (n < 0) throw InputError("CLI: negative hatch count", path);
            for (long k = 0; k < n; ++k) {
                std::array<double, 4> l;
                for (double& v : l) v = (isLong ? in.f32() : in.u16()) * u;
                hatches.lines.push_back(l);
            }
            currentLayer(file, path).hatches.push_back(std::move(hatches));
        } else {
            throw InputError("CLI: unknown binary command " + std::to_string(command), path);
        }
    }
}

void readAscii(CliFile& file, const std::string& data, size_t pos, const std::string& path) {
    const size_t start = data.find("$$GEOMETRYSTART", pos);
    if (start == std::string::npos) throw InputError("CLI: no $$GEOMETRYSTART", path);
    const double u = file.units;
    // Commands start with "$$"; their parameters run to the next command (may span lines).
    size_t at = data.find("$$", start + 2);
    while (at != std::string::npos) {
        size_t next = data.find("$$", at + 2);
        std::string command = trim(
            data.substr(at + 2, next == std::string::npos ? std::string::npos : next - at - 2));
        at = next;
        if (command == "GEOMETRYEND") return;
        const size_t slash = command.find('/');
        const std::string name = command.substr(0, slash);
        const std::vector<double> v = slash == std::string::npos
                                          ? std::vector<double>{}
                                          : numbers(command.substr(slash + 1), path);
        if (name == "LAYER") {
            if (v.size() != 1) throw InputError("CLI: $$LAYER needs one z", path);
            file.layers.push_back({});
            file.layers.back().z = v[0] * u;
        } else if (name == "POLYLINE") {
            if (v.size() < 3 || v.size() != 3 + 2 * size_t(v[2]))
                throw InputError("CLI: $$POLYLINE point count does not match", path);
            CliPolyline line;
            line.id = int(v[0]), line.direction = int(v[1]);
            for (size_t k = 3; k < v.size(); k += 2)
                line.points.push_back({v[k] * u, v[k + 1] * u});
            currentLayer(file, path).polylines.push_back(std::move(line));
        } else if (name == "HATCHES") {
            if (v.size() < 2 || v.size() != 2 + 4 * size_t(v[1]))
                throw InputError("CLI: $$HATCHES count does not match", path);
            CliHatches hatches;
            hatches.id = int(v[0]);
            for (size_t k = 2; k < v.size(); k += 4)
                hatches.lines.push_back({v[k] * u, v[k + 1] * u, v[k + 2] * u, v[k + 3] * u});
            currentLayer(file, path).hatches.push_back(std::move(hatches));
        } else {
            throw InputError("CLI: unknown command $$" + name, path);
        }
    }
    throw InputError("CLI: no $$GEOMETRYEND", path);
}

}  // namespace

CliFile readCli(const std::string& path) {
    const std::string data = readFile(path);
    const size_t begin = data.find("$$HEADERSTART"), end = data.find("$$HEADEREND");
    if (begin == std::string::npos || end == std::string::npos || end < begin)
        throw InputError("CLI: no $$HEADERSTART ... $$HEADEREND header", path);
    CliFile file;
    bool formatSeen = false;
    std::stringstream header(data.substr(begin, end - begin));
    std::string line;
    while (std::getline(header, line)) {
        line = trim(line);
        if (line == "$$BINARY" || line == "$$ASCII")
            file.binary = line == "$$BINARY", formatSeen = true;
        else if (line.rfind("$$UNITS/", 0) == 0)
            file.units = numbers(line.substr(8), path).at(0);
        else if (line.rfind("$$VERSION/", 0) == 0)
            file.version = int(numbers(line.substr(10), path).at(0));
        else if (line.rfind("$$LAYERS/", 0) == 0)
            file.declaredLayers = int(numbers(line.substr(9), path).at(0));
    }
    if (!formatSeen) throw InputError("CLI: header says neither $$ASCII nor $$BINARY", path);
    if (!(file.units > 0)) throw InputError("CLI: $$UNITS must be positive", path);
    const size_t geometry = end + std::strlen("$$HEADEREND");
    if (file.binary)
        readBinary(file, data, geometry, path);
    else
        readAscii(file, data, geometry, path);
    return file;
}

}  // namespace vpsim::exporters
