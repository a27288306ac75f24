#include "vpsim/exporters/grey_masks.h"

#include <png.h>

#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim::exporters {
namespace {

void appendPng(png_structp png, png_bytep data, png_size_t length) {
    auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + length);
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

KeyTable greyLevelKeyTable() {
    return {{
        tableKey("grey_levels", "projector calibration: [[grey, irradiance], ...]")
            .requiredLike(nlohmann::json::array(
                {{150, "12.2 mW/cm^2"}, {200, "17 mW/cm^2"}, {255, "27 mW/cm^2"}})),
        quantityKey("exposure_time", dim::TIME, nullptr, "one exposure per layer")
            .positiveOnly()
            .requiredLike("5 s"),
    }};
}

plan::GreyLevels greyLevelsFromKeys(const KeyReader& keys) {
    keys.raw("grey_levels");
    keys.quantity("exposure_time");
    return plan::greyLevelsFromConfig(keys.node());
}

}  // namespace vpsim::exporters
