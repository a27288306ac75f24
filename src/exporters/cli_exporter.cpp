#include "vpsim/exporters/cli_exporter.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim::exporters {
namespace {

struct Segment {
    double x0, y0, x1, y1;
};

/// A run of the layer's geometry in scan order: a polyline (chained marks) or hatches.
struct Block {
    bool polyline = false;
    int direction = 2;
    std::vector<glm::dvec2> points;  // polyline
    std::vector<Segment> lines;      // hatches
};

bool chained(const Segment& a, const Segment& b) {
    return std::abs(a.x1 - b.x0) <= 1e-9 && std::abs(a.y1 - b.y0) <= 1e-9;
}

std::vector<Segment> layerMarks(const plan::LayerPlan& layer) {
    std::vector<Segment> marks;
    if (!layer.trajectory.empty()) {
        for (const plan::ScanMove& m : layer.trajectory)
            if (m.laserOn) marks.push_back({m.x0, m.y0, m.x1, m.y1});
        return marks;
    }
    for (const auto& v : layer.vectors) marks.push_back({v.x0, v.y0, v.x1, v.y1});
    for (const auto& p : layer.points) marks.push_back({p.x, p.y, p.x, p.y});
    return marks;
}

std::vector<Block> layerBlocks(const plan::LayerPlan& layer) {
    const std::vector<Segment> marks = layerMarks(layer);
    std::vector<Block> blocks;
    for (size_t i = 0; i < marks.size();) {
        // A chain ends where it closes (a border followed by hatches starting on it stays a
        // closed polyline) or where the next mark does not start at its end.
        auto closes = [&](size_t last) {
            return last >= i + 2 && std::abs(marks[last].x1 - marks[i].x0) <= 1e-9 &&
                   std::abs(marks[last].y1 - marks[i].y0) <= 1e-9;
        };
        size_t j = i + 1;
        while (j < marks.size() && chained(marks[j - 1], marks[j]) && !closes(j - 1)) ++j;
        if (j - i >= 2) {
            Block b;
            b.polyline = true;
            b.points.push_back({marks[i].x0, marks[i].y0});
            for (size_t k = i; k < j; ++k) b.points.push_back({marks[k].x1, marks[k].y1});
            const glm::dvec2 &first = b.points.front(), &last = b.points.back();
            if (std::abs(first.x - last.x) <= 1e-9 && std::abs(first.y - last.y) <= 1e-9) {
                double area = 0;
                for (size_t k = 0; k + 1 < b.points.size(); ++k)
                    area += b.points[k].x * b.points[k + 1].y - b.points[k + 1].x * b.points[k].y;
                b.direction = area > 0 ? 1 : 0;
            }
            blocks.push_back(std::move(b));
        } else {
            if (blocks.empty() || blocks.back().polyline) blocks.emplace_back();
            blocks.back().lines.push_back(marks[i]);
        }
        i = j;
    }
    return blocks;
}

std::string number(double value) {
    char text[64];
    std::snprintf(text, sizeof text, "%.3f", value);
    std::string s = text;
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    if (s == "-0") s = "0";
    return s;
}

void putU16(std::string& out, uint16_t v) {
    out.push_back(char(v & 0xff));
    out.push_back(char(v >> 8));
}
void putI32(std::string& out, int32_t value) {
    uint32_t v;
    std::memcpy(&v, &value, 4);
    for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8 * k)) & 0xff));
}
void putF32(std::string& out, double value) {
    float f = float(value);
    uint32_t v;
    std::memcpy(&v, &f, 4);
    for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8 * k)) & 0xff));
}

std::string header(const plan::ScanPlan& plan, const CliOptions& options) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    auto grow = [&](double x, double y, double z) {
        const double p[3] = {x, y, z};
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    };
    for (const auto& layer : plan.layers)
        for (const Segment& s : layerMarks(layer))
            grow(s.x0, s.y0, layer.z), grow(s.x1, s.y1, layer.z);
    if (!std::isfinite(lo[0])) std::fill(lo, lo + 3, 0.0), std::fill(hi, hi + 3, 0.0);
    char units[64], dimension[256];
    std::snprintf(units, sizeof units, "%.8f", options.units);
    std::snprintf(dimension, sizeof dimension, "%.6f,%.6f,%.6f,%.6f,%.6f,%.6f", lo[0], lo[1], lo[2],
                  hi[0], hi[1], hi[2]);
    std::string h = "$$HEADERSTART\n";
    h += options.binary ? "$$BINARY\n" : "$$ASCII\n";
    h += std::string("$$UNITS/") + units + "\n$$VERSION/200\n$$LABEL/1,vpsim\n";
    h += std::string("$$DIMENSION/") + dimension + "\n";
    h += "$$LAYERS/" + std::to_string(plan.layers.size()) + "\n";
    // Binary data follows $$HEADEREND directly (readers seek to the byte after it).
    h += options.binary ? "$$HEADEREND" : "$$HEADEREND\n";
    return h;
}

std::string asciiGeometry(const plan::ScanPlan& plan, double u) {
    std::string out = "$$GEOMETRYSTART\n";
    for (const auto& layer : plan.layers) {
        out += "$$LAYER/" + number(layer.z / u) + "\n";
        for (const Block& b : layerBlocks(layer)) {
            if (b.polyline) {
                out += "$$POLYLINE/1," + std::to_string(b.direction) + "," +
                       std::to_string(b.points.size());
                for (const auto& p : b.points) out += "," + number(p.x / u) + "," + number(p.y / u);
            } else {
                out += "$$HATCHES/1," + std::to_string(b.lines.size());
                for (const Segment& s : b.lines)
                    out += "," + number(s.x0 / u) + "," + number(s.y0 / u) + "," +
                           number(s.x1 / u) + "," + number(s.y1 / u);
            }
            out += "\n";
        }
    }
    return out + "$$GEOMETRYEND\n";
}

std::string binaryGeometry(const plan::ScanPlan& plan, double u) {
    std::string out;
    for (const auto& layer : plan.layers) {
        putU16(out, 127);
        putF32(out, layer.z / u);
        for (const Block& b : layerBlocks(layer)) {
            if (b.polyline) {
                putU16(out, 130);
                putI32(out, 1), putI32(out, b.direction), putI32(out, int32_t(b.points.size()));
                for (const auto& p : b.points) putF32(out, p.x / u), putF32(out, p.y / u);
            } else {
                putU16(out, 132);
                putI32(out, 1), putI32(out, int32_t(b.lines.size()));
                for (const Segment& s : b.lines)
                    putF32(out, s.x0 / u), putF32(out, s.y0 / u), putF32(out, s.x1 / u),
                        putF32(out, s.y1 / u);
            }
        }
    }
    return out;
}

}  // namespace

KeyTable cliKeyTable() {
    return {{
        choiceKey("format", {"ascii", "binary"}, "ascii", "the geometry section's encoding"),
        quantityKey("units", dim::LENGTH, "1 um", "length of one coordinate unit ($$UNITS)")
            .positiveOnly(),
    }};
}

CliOptions cliOptionsFromKeys(const KeyReader& keys) {
    CliOptions cli;
    cli.binary = keys.choice("format") == "binary";
    cli.units = keys.quantity("units");
    return cli;
}

bool CliExporter::accepts(const plan::ScanPlan& plan, std::string& reason) const {
    for (const auto& layer : plan.layers)
        if (!layer.vectors.empty() || !layer.points.empty() || !layer.trajectory.empty())
            return true;
    reason = "CLI holds laser vectors and points; this plan has none (a DLP plan?)";
    return false;
}

void CliExporter::write(const plan::ScanPlan& plan, const std::string& path) const {
    std::string contents = header(plan, mOptions);
    contents += mOptions.binary ? binaryGeometry(plan, mOptions.units)
                                : asciiGeometry(plan, mOptions.units);
    writeFileAtomic(path, contents);
}

void registerCliExporter(ExporterRegistry& registry) {
    registry.add({"cli", "Common Layer Interface: polylines and hatches per layer (laser machines)",
                  cliKeyTable(), [](const KeyReader& keys) {
                      return std::make_unique<CliExporter>(cliOptionsFromKeys(keys));
                  }});
}

size_t CliLayer::vectorCount() const {
    size_t n = 0;
    for (const auto& p : polylines) n += p.points.empty() ? 0 : p.points.size() - 1;
    for (const auto& h : hatches) n += h.lines.size();
    return n;
}

}  // namespace vpsim::exporters
