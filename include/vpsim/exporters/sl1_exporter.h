#pragma once
/// @file
/// PrusaSlicer SL1 archives for greyscale DLP printers.
///
/// An SL1 file is a zip of `config.ini` (what the printer firmware reads: jobDir, layerHeight,
/// expTime, expTimeFirst, numFade, numSlow/numFast, printTime, ...), `prusaslicer.ini` (the
/// slicer's profile; tools such as UVtools take the display's pixel counts and size from its
/// display_pixels_x/y and display_width/height) and one 8-bit greyscale PNG per layer named
/// jobDir + five-digit index. Each mask pixel's dose is mapped to a grey level through the
/// projector's calibration (plan::GreyLevels; dose = irradiance(grey) x exposure time), so the
/// archive carries one exposure time and the per-pixel doses in its grey levels.
/// Written with libzip (Debian) to a temporary file renamed into place.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vpsim/exporters/exporter.h"
#include "vpsim/plan/grey_levels.h"

namespace vpsim::exporters {

/// Display and job settings of an SL1 archive.
struct Sl1Settings {
    std::string jobName = "print";     ///< jobDir and layer-file prefix
    std::string printerModel = "SL1";  ///< printerModel in config.ini
    int displayPixelsX = 0;            ///< 0: the mask width
    int displayPixelsY = 0;            ///< 0: the mask height
    double displayWidth = 0.0;         ///< mm; 0: pixels x pitch
    double displayHeight = 0.0;        ///< mm; 0: pixels x pitch
    int fadeLayers = 0;                ///< numFade (layers of exposure ramp; greyscale needs none)
};

class Sl1Exporter : public Exporter {
public:
    Sl1Exporter(plan::GreyLevels levels, Sl1Settings settings);
    std::string defaultFileName() const override { return "print.sl1"; }
    /// Needs exactly one mask per layer, all of the same size and pitch.
    bool accepts(const plan::ScanPlan& plan, std::string& reason) const override;
    /// @throw InputError when the plan is not accepted or the archive cannot be written
    void write(const plan::ScanPlan& plan, const std::string& path) const override;
    /// Creates one from its options section: grey_levels, exposure_time (as in the machine
    /// section), and optional job_name, printer_model, display_pixels_x/y, display_width/height,
    /// fade_layers. @throw InputError naming the key
    static std::unique_ptr<Exporter> fromConfig(const KeyReader& keys);

private:
    plan::GreyLevels mLevels;
    Sl1Settings mSettings;
};

/// Adds "sl1" to a registry.
void registerSl1Exporter(ExporterRegistry& registry);

}  // namespace vpsim::exporters
