#pragma once
/// @file
/// A plain PNG stack for DLP printers: a directory of 8-bit greyscale masks, one per layer,
/// through the projector's calibration (grey_masks.h).

#include <memory>
#include <string>

#include "vpsim/exporters/exporter.h"
#include "vpsim/plan/grey_levels.h"

namespace vpsim::exporters {

/// A directory of 8-bit greyscale PNGs, one per layer (layer00000.png, ...), plus masks.json
/// with the exposure time and pixel pitch.
class PngStackExporter : public Exporter {
public:
    explicit PngStackExporter(plan::GreyLevels levels) : mLevels(std::move(levels)) {}
    std::string defaultFileName() const override { return "masks"; }
    bool accepts(const plan::ScanPlan& plan, std::string& reason) const override;
    /// `path` is a directory (created). @throw InputError when a file cannot be written
    void write(const plan::ScanPlan& plan, const std::string& path) const override;
    static std::unique_ptr<Exporter> fromConfig(const KeyReader& keys);

private:
    plan::GreyLevels mLevels;
};

/// Adds "png-stack" to a registry.
void registerPngStackExporter(ExporterRegistry& registry);

}  // namespace vpsim::exporters
