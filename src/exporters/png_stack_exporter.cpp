#include "vpsim/exporters/png_stack_exporter.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"
#include "vpsim/exporters/grey_masks.h"

namespace vpsim::exporters {

bool PngStackExporter::accepts(const plan::ScanPlan& plan, std::string& reason) const {
    for (size_t k = 0; k < plan.layers.size(); ++k)
        if (plan.layers[k].masks.size() != 1)
            return reason = "layer " + std::to_string(k) + " is not exactly one mask", false;
    return !plan.layers.empty() || (reason = "the plan has no layers", false);
}

void PngStackExporter::write(const plan::ScanPlan& plan, const std::string& path) const {
    std::string reason;
    if (!accepts(plan, reason)) throw InputError("PNG stack: " + reason, path);
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (ec) throw InputError("PNG stack: cannot create the directory", path);
    char name[64];
    Progress progress("PNG stack export: layer images written", plan.layers.size());
    for (size_t k = 0; k < plan.layers.size(); ++k) {
        const plan::MaskImage& m = plan.layers[k].masks[0];
        std::vector<uint8_t> png = encodePngGrey(m.width, m.height, maskToGrey(m, mLevels));
        std::snprintf(name, sizeof name, "/layer%05zu.png", k);
        writeFileAtomic(path + name, std::string(png.begin(), png.end()));
        progress.advance();
    }
    std::ostringstream index;
    index << "{\"layers\": " << plan.layers.size()
          << ", \"exposure_time_s\": " << formatNumber(mLevels.exposureTime())
          << ", \"pixel_pitch_mm\": " << formatNumber(plan.layers[0].masks[0].pixelPitch)
          << ", \"layer_thickness_mm\": " << formatNumber(plan.machine.layerThickness) << "}\n";
    writeFileAtomic(path + "/masks.json", index.str());
}

std::unique_ptr<Exporter> PngStackExporter::fromConfig(const KeyReader& keys) {
    return std::make_unique<PngStackExporter>(greyLevelsFromKeys(keys));
}

void registerPngStackExporter(ExporterRegistry& registry) {
    registry.add({"png-stack", "directory of 8-bit greyscale PNG masks, one per layer",
                  greyLevelKeyTable(), &PngStackExporter::fromConfig});
}

}  // namespace vpsim::exporters
