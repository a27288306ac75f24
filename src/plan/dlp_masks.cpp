#include "vpsim/plan/dlp_masks.h"

#include "vpsim/core/error.h"

namespace vpsim::plan {

MaskImage uniformMask(const geometry::PolygonSet& region, const geometry::RasterGrid& grid,
                      double dose, MaskRasterMode mode) {
    if (!(dose >= 0)) throw InputError("mask dose must not be negative");
    MaskImage mask;
    mask.width = grid.width;
    mask.height = grid.height;
    mask.originX = grid.origin.x;
    mask.originY = grid.origin.y;
    mask.pixelPitch = grid.pitch;
    mask.dose.assign(grid.pixelCount(), 0.0f);
    if (mode == MaskRasterMode::Binary) {
        std::vector<uint8_t> inside = geometry::rasterizeBinary(region, grid);
        for (size_t p = 0; p < inside.size(); ++p) mask.dose[p] = inside[p] ? float(dose) : 0.0f;
    } else {
        std::vector<double> coverage = geometry::rasterizeCoverage(region, grid);
        for (size_t p = 0; p < coverage.size(); ++p) mask.dose[p] = float(dose * coverage[p]);
    }
    return mask;
}

}  // namespace vpsim::plan
