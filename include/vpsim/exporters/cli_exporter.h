#pragma once
/// @file
/// Common Layer Interface (CLI) export and read-back. The header is ASCII between $$HEADERSTART
/// and $$HEADEREND ($$ASCII or $$BINARY, $$UNITS = mm per coordinate unit, $$VERSION/200,
/// $$LABEL, $$DIMENSION in mm, $$LAYERS); the geometry is per layer $$LAYER/z, $$POLYLINE/id,
/// dir, n, x y... (dir 0 clockwise, 1 counter-clockwise, 2 open) and $$HATCHES/id, n,
/// x1 y1 x2 y2..., ASCII between $$GEOMETRYSTART and $$GEOMETRYEND, or binary right after
/// $$HEADEREND as little-endian uint16 command ids with their parameters: 127 layer (float32 z),
/// 128 layer (uint16 z), 129 polyline (uint16 id, dir, n, n uint16 pairs), 130 polyline (int32
/// id, dir, n, n float32 pairs), 131 hatches (uint16 id, n, 4n uint16), 132 hatches (int32 id, n,
/// 4n float32). vpsim writes the long forms (127, 130, 132) and reads all six.
///
/// What is written: each layer's trajectory marks when the plan has one (else its vectors in plan
/// order); runs of chained marks become polylines (closed loops with their orientation), single
/// marks hatches; points become zero-length hatches. Power and speed are not part of CLI.

#include <array>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "vpsim/exporters/exporter.h"

namespace vpsim::exporters {

struct CliOptions {
    bool binary = false;  ///< `format`: "ascii" (default) | "binary"
    double units =
        1e-3;  ///< mm per coordinate unit (`units`, e.g. "1 um"); ASCII writes 3 decimals
};

/// The exporter's keys (format, units) and the options they give. @throw InputError naming the key
KeyTable cliKeyTable();
CliOptions cliOptionsFromKeys(const KeyReader& keys);

class CliExporter : public Exporter {
public:
    explicit CliExporter(CliOptions options = {}) : mOptions(options) {}
    std::string defaultFileName() const override { return "scan.cli"; }
    bool accepts(const plan::ScanPlan& plan, std::string& reason) const override;
    /// @throw InputError when the file cannot be written
    void write(const plan::ScanPlan& plan, const std::string& path) const override;

private:
    CliOptions mOptions;
};

/// Adds "cli" to `registry`.
void registerCliExporter(ExporterRegistry& registry);

struct CliPolyline {
    int id = 1, direction = 2;       ///< 0 clockwise, 1 counter-clockwise, 2 open
    std::vector<glm::dvec2> points;  ///< mm
};
struct CliHatches {
    int id = 1;
    std::vector<std::array<double, 4>> lines;  ///< x1 y1 x2 y2, mm
};
struct CliLayer {
    double z = 0;  ///< mm
    std::vector<CliPolyline> polylines;
    std::vector<CliHatches> hatches;
    /// Vectors: polyline segments plus hatch lines.
    size_t vectorCount() const;
};
struct CliFile {
    bool binary = false;
    double units = 1;              ///< mm per unit
    int version = 0;               ///< e.g. 200
    int declaredLayers = -1;       ///< $$LAYERS, -1 when absent
    std::vector<CliLayer> layers;  ///< coordinates converted to mm
};

/// Reads an ASCII or binary CLI file. @throw InputError naming the file and the problem
CliFile readCli(const std::string& path);

}  // namespace vpsim::exporters
