#include "vpsim/exporters/sl1_exporter.h"
#include "vpsim/core/text.h"

#include <png.h>
#include <zip.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/io.h"

namespace vpsim::exporters {
namespace {

void appendPng(png_structp png, png_bytep data, png_size_t length) {
    auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + length);
}

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

std::vector<uint8_t> maskToGrey(const plan::MaskImage& mask, const plan::GreyLevels& levels) {
    std::vector<uint8_t> grey(mask.dose.size());
    for (size_t i = 0; i < grey.size(); ++i) {
        const double d = mask.dose[i];
        if (!(d >= 0.0) || !std::isfinite(d))
            throw InputError("mask dose must be finite and >= 0 for grey levels");
        if (d > levels.maxDose() * 1.005)
            throw InputError("mask dose " + formatNumber(d * 100.0) +
                             " mJ/cm^2 exceeds the projector's brightest grey (" +
                             formatNumber(levels.maxDose() * 100.0) + " mJ/cm^2)");
        grey[i] = levels.quantise(d);
    }
    return grey;
}

std::vector<uint8_t> encodePngGrey(int width, int height, const std::vector<uint8_t>& grey) {
    if (width <= 0 || height <= 0 || grey.size() != size_t(width) * size_t(height))
        throw InputError("PNG: image size does not match its pixels");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) throw InputError("PNG: libpng could not start");
    std::vector<uint8_t> out;
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        throw InputError("PNG: libpng failed to encode a layer");
    }
    png_set_write_fn(png, &out, appendPng, nullptr);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_GRAY,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y)
        png_write_row(png, const_cast<png_bytep>(grey.data() + size_t(y) * size_t(width)));
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

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
    for (size_t k = 0; k < n; ++k)
        images[k] = encodePngGrey(px, py, displayImage(plan.layers[k].masks[0], mLevels, px, py));

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

std::unique_ptr<Exporter> Sl1Exporter::fromConfig(const ConfigNode& section) {
    Sl1Settings s;
    s.jobName = section.string("job_name", std::string("print"));
    s.printerModel = section.string("printer_model", std::string("SL1"));
    s.displayPixelsX = int(section.integer("display_pixels_x", 0));
    s.displayPixelsY = int(section.integer("display_pixels_y", 0));
    s.displayWidth = section.quantity("display_width", dim::LENGTH, 0.0);
    s.displayHeight = section.quantity("display_height", dim::LENGTH, 0.0);
    s.fadeLayers = int(section.integer("fade_layers", 0));
    if (s.displayPixelsX < 0 || s.displayPixelsY < 0 || s.fadeLayers < 0)
        throw section.error("display_pixels_x", "display sizes and fade layers must be >= 0");
    return std::make_unique<Sl1Exporter>(plan::greyLevelsFromConfig(section), s);
}

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
    for (size_t k = 0; k < plan.layers.size(); ++k) {
        const plan::MaskImage& m = plan.layers[k].masks[0];
        std::vector<uint8_t> png = encodePngGrey(m.width, m.height, maskToGrey(m, mLevels));
        std::snprintf(name, sizeof name, "/layer%05zu.png", k);
        writeFileAtomic(path + name, std::string(png.begin(), png.end()));
    }
    std::ostringstream index;
    index << "{\"layers\": " << plan.layers.size()
          << ", \"exposure_time_s\": " << formatNumber(mLevels.exposureTime())
          << ", \"pixel_pitch_mm\": " << formatNumber(plan.layers[0].masks[0].pixelPitch)
          << ", \"layer_thickness_mm\": " << formatNumber(plan.machine.layerThickness) << "}\n";
    writeFileAtomic(path + "/masks.json", index.str());
}

std::unique_ptr<Exporter> PngStackExporter::fromConfig(const ConfigNode& section) {
    return std::make_unique<PngStackExporter>(plan::greyLevelsFromConfig(section));
}

void registerSl1Exporters(ExporterRegistry& registry) {
    registry.add({"sl1",
                  "PrusaSlicer SL1 archive: config.ini, prusaslicer.ini, 8-bit grey PNG per layer",
                  {{"grey_levels", "[[grey, irradiance mW/mm^2], ...] projector calibration"},
                   {"exposure_time", "s, one exposure per layer"},
                   {"display_pixels_x", "display pixels (default: the mask width)"},
                   {"display_pixels_y", "display pixels (default: the mask height)"},
                   {"display_width", "mm (default: pixels x pitch)"},
                   {"display_height", "mm (default: pixels x pitch)"},
                   {"job_name", "jobDir and layer-file prefix (default print)"},
                   {"printer_model", "printerModel (default SL1)"},
                   {"fade_layers", "numFade (default 0)"}},
                  &Sl1Exporter::fromConfig});
    registry.add({"png-stack",
                  "directory of 8-bit greyscale PNG masks, one per layer",
                  {{"grey_levels", "[[grey, irradiance mW/mm^2], ...]"}, {"exposure_time", "s"}},
                  &PngStackExporter::fromConfig});
}

}  // namespace vpsim::exporters
