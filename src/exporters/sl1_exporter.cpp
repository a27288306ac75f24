#include "vpsim/exporters/sl1_exporter.h"

#include <png.h>
#include <zip.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/text.h"
#include "vpsim/exporters/grey_masks.h"

namespace vpsim::exporters {
namespace {

/// The layer's grey image placed on the display (centred; pixels outside the mask are 0).
std::vector<uint8_t> displayImage(const plan::MaskImage& mask, const plan::GreyLevels& levels,
                                  int width, int height) {
    std::vector<uint8_t> grey = maskToGrey(mask, levels);
    if (width == mask.width && height == mask.height) return grey;
    std::vector<uint8_t> out(size_t(width) * size_t(height), 0);
    const int x0 = (width - mask.width) / 2, y0 = (height - mask.height) / 2;
    for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x)
            out[size_t(y + y0) * size_t(width) + size_t(x + x0)] =
                grey[size_t(y) * size_t(mask.width) + size_t(x)];
    return out;
}

}  // namespace

Sl1Exporter::Sl1Exporter(plan::GreyLevels levels, Sl1Settings settings)
    : mLevels(std::move(levels)), mSettings(std::move(settings)) {}

bool Sl1Exporter::accepts(const plan::ScanPlan& plan, std::string& reason) const {
    if (plan.layers.empty()) return reason = "the plan has no layers", false;
    const auto& first = plan.layers.front();
    for (size_t k = 0; k < plan.layers.size(); ++k) {
        const auto& layer = plan.layers[k];
        if (layer.masks.size() != 1 || !layer.points.empty() || !layer.vectors.empty())
            return reason = "layer " + std::to_string(k) + " is not exactly one mask", false;
        const auto& m = layer.masks[0];
        if (first.masks.empty() || m.width != first.masks[0].width ||
            m.height != first.masks[0].height || m.pixelPitch != first.masks[0].pixelPitch)
            return reason = "the masks of layer " + std::to_string(k) + " differ in size", false;
        if ((mSettings.displayPixelsX && m.width > mSettings.displayPixelsX) ||
            (mSettings.displayPixelsY && m.height > mSettings.displayPixelsY))
            return reason = "the masks are larger than the display", false;
    }
    return true;
}

void Sl1Exporter::write(const plan::ScanPlan& plan, const std::string& path) const {
    std::string reason;
    if (!accepts(plan, reason)) throw InputError("SL1: " + reason, path);
    const plan::MaskImage& m0 = plan.layers.front().masks.front();
    const int px = mSettings.displayPixelsX ? mSettings.displayPixelsX : m0.width;
    const int py = mSettings.displayPixelsY ? mSettings.displayPixelsY : m0.height;
    const double width = mSettings.displayWidth > 0 ? mSettings.displayWidth : px * m0.pixelPitch;
    const double height =
        mSettings.displayHeight > 0 ? mSettings.displayHeight : py * m0.pixelPitch;
    const double t = mLevels.exposureTime();
    const size_t n = plan.layers.size();
    std::ostringstream config;  // config.ini: what the firmware reads
    config << "action = print\nexpTime = " << formatNumber(t)
           << "\nexpTimeFirst = " << formatNumber(t)
           << "\nexpUserProfile = 0\nfileCreationTimestamp = vpsim\nhollow = 0\njobDir = "
           << mSettings.jobName << "\nlayerHeight = " << formatNumber(plan.machine.layerThickness)
           << "\nmaterialName = vpsim\nnumFade = " << mSettings.fadeLayers << "\nnumFast = " << n
           << "\nnumSlow = 0\nprintProfile = vpsim optimised-mask"
           << "\nprinterModel = " << mSettings.printerModel
           << "\nprinterProfile = vpsim\nprinterVariant = default\nprintTime = "
           << formatNumber(double(n) * t) << "\nprusaSlicerVersion = vpsim " << VPSIM_VERSION
           << "\nusedMaterial = 0\n";
    std::ostringstream profile;  // prusaslicer.ini: the display geometry tools read
    profile << "printer_technology = SLA\ndisplay_pixels_x = " << px
            << "\ndisplay_pixels_y = " << py << "\ndisplay_width = " << formatNumber(width)
            << "\ndisplay_height = " << formatNumber(height)
            << "\ndisplay_orientation = landscape\ndisplay_mirror_x = 0\ndisplay_mirror_y = 0"
            << "\nexposure_time = " << formatNumber(t)
            << "\ninitial_exposure_time = " << formatNumber(t)
            << "\nlayer_height = " << formatNumber(plan.machine.layerThickness)
            << "\nfaded_layers = " << mSettings.fadeLayers
            << "\nprinter_model = " << mSettings.printerModel << "\n";
    std::vector<std::string> texts{config.str(), profile.str()};
    std::vector<std::vector<uint8_t>> images(n);
    Progress progress("SL1 export: layer images encoded", n);
    for (size_t k = 0; k < n; ++k) {
        images[k] = encodePngGrey(px, py, displayImage(plan.layers[k].masks[0], mLevels, px, py));
        progress.advance();
    }
    progress.finish();

    const std::string temporary = path + ".tmp";
    std::remove(temporary.c_str());
    int error = 0;
    zip_t* archive = zip_open(temporary.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
    if (!archive) throw InputError("SL1: cannot create the archive", path);
    auto add = [&](const std::string& name, const void* data, size_t size) {
        zip_source_t* source = zip_source_buffer(archive, data, size, 0);
        if (!source || zip_file_add(archive, name.c_str(), source, ZIP_FL_OVERWRITE) < 0) {
            if (source) zip_source_free(source);
            zip_discard(archive);
            throw InputError("SL1: cannot add " + name + " to the archive", path);
        }
    };
    add("config.ini", texts[0].data(), texts[0].size());
    add("prusaslicer.ini", texts[1].data(), texts[1].size());
    char name[64];
    for (size_t k = 0; k < n; ++k) {
        std::snprintf(name, sizeof name, "%05zu.png", k);
        add(mSettings.jobName + name, images[k].data(), images[k].size());
    }
    if (zip_close(archive) != 0) {
        zip_discard(archive);
        throw InputError("SL1: cannot write the archive", path);
    }
    std::filesystem::rename(temporary, path);
}

namespace {

KeyTable sl1KeyTable() {
    KeyTable table = greyLevelKeyTable();
    table.add({{
        integerKey("display_pixels_x", 0, "display pixels (0: the mask width)").in(0, 1e6),
        integerKey("display_pixels_y", 0, "display pixels (0: the mask height)").in(0, 1e6),
        quantityKey("display_width", dim::LENGTH, 0, "display width (0: pixels x pitch)")
            .in(0, INFINITY),
        quantityKey("display_height", dim::LENGTH, 0, "display height (0: pixels x pitch)")
            .in(0, INFINITY),
        stringKey("job_name", "print", "jobDir and layer-file prefix"),
        stringKey("printer_model", "SL1", "printerModel in config.ini"),
        integerKey("fade_layers", 0, "numFade: layers of exposure ramp").in(0, 1e6),
    }});
    return table;
}

}  // namespace

std::unique_ptr<Exporter> Sl1Exporter::fromConfig(const KeyReader& keys) {
    Sl1Settings s;
    s.jobName = keys.string("job_name");
    s.printerModel = keys.string("printer_model");
    s.displayPixelsX = int(keys.integer("display_pixels_x"));
    s.displayPixelsY = int(keys.integer("display_pixels_y"));
    s.displayWidth = keys.quantity("display_width");
    s.displayHeight = keys.quantity("display_height");
    s.fadeLayers = int(keys.integer("fade_layers"));
    return std::make_unique<Sl1Exporter>(greyLevelsFromKeys(keys), s);
}

void registerSl1Exporter(ExporterRegistry& registry) {
    registry.add({"sl1",
                  "PrusaSlicer SL1 archive: config.ini, prusaslicer.ini, 8-bit grey PNG per layer",
                  sl1KeyTable(), &Sl1Exporter::fromConfig});
}

}  // namespace vpsim::exporters
