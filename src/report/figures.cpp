#include "vpsim/report/figures.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/image.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/geometry/slicer.h"

namespace vpsim::report {
namespace {

/// Draws a scalar field with outlines of two masks, scaled up by an integer factor to about 800 px.
RgbImage outlinedMap(const std::vector<float>& values, const std::vector<uint8_t>& reference,
                     int width, int height, const cure::CureLaw& law) {
    int scale = std::max(1, std::min(8, 800 / std::max(width, height)));
    std::vector<float> big(size_t(width) * scale * height * scale);
    auto index = [&](int x, int y) { return size_t(y) * width + x; };
    for (int y = 0; y < height * scale; ++y)
        for (int x = 0; x < width * scale; ++x)
            big[size_t(y) * width * scale + x] = values[index(x / scale, y / scale)];
    // Linear from 0 to the 99th percentile of the exposure shown (hot spots saturate), and at
    // least twice Ec so the cure level sits inside the scale.
    std::vector<float> sorted(values);
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() * 99 / 100, sorted.end());
    double top = std::max(2.0 * law.criticalDose(), double(sorted[sorted.size() * 99 / 100]));
    RgbImage image = heatMap(big, width * scale, height * scale, 0.0, top);
    auto edge = [&](auto inside, int x, int y) {
        bool here = inside(x, y);
        return (x + 1 < width && inside(x + 1, y) != here) ||
               (y + 1 < height && inside(x, y + 1) != here);
    };
    auto cured = [&](int x, int y) { return law.isCured(values[index(x, y)]); };
    auto ref = [&](int x, int y) { return reference[index(x, y)] != 0; };
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int d = 0; d < scale; ++d) {
                if (edge(ref, x, y))
                    image.set(x * scale + scale - 1, y * scale + d, 230, 30, 30),
                        image.set(x * scale + d, y * scale + scale - 1, 230, 30, 30);
                if (edge(cured, x, y))
                    image.set(x * scale + scale / 2, y * scale + d, 255, 255, 255),
                        image.set(x * scale + d, y * scale + scale / 2, 255, 255, 255);
            }
    return image;
}

}  // namespace

SectionRecorder::SectionRecorder(const geometry::Mesh& part, const exposure::ExposureGrid& grid,
                                 int totalSlices, const cure::CureLaw& law, int mapLayer, int row)
    : mPart(part),
      mGrid(grid),
      mLaw(law),
      mMapLayer(mapLayer),
      mRow(row),
      mTotalSlices(totalSlices),
      mSection(size_t(totalSlices) * grid.nx, 0.0f),
      mSectionInside(size_t(totalSlices) * grid.nx, 0) {}

void SectionRecorder::add(const exposure::ExposureSlice& slice) {
    if (mFilled >= mTotalSlices) return;
    geometry::PolygonSet region = geometry::sliceAt(mPart, slice.z);
    const exposure::SurfaceGrid& values = *slice.values;
    for (int i = 0; i < mGrid.nx; ++i) {
        mSection[size_t(mFilled) * mGrid.nx + i] = values.at(i, mRow);
        mSectionInside[size_t(mFilled) * mGrid.nx + i] =
            region.contains({values.centreX(i), values.centreY(mRow)});
    }
    ++mFilled;
    if (slice.layer == mMapLayer && slice.slice == mGrid.slicesPerLayer / 2) {
        mMapInside = geometry::flipRows(geometry::rasterizeBinary(region, mGrid.raster()), mGrid.nx,
                                        mGrid.ny);
        mMap = geometry::flipRows(values.values, mGrid.nx, mGrid.ny);  // image rows run top-down
    }
}

int busiestRow(const geometry::PolygonSet& region, const exposure::ExposureGrid& grid) {
    std::vector<uint8_t> inside = geometry::rasterizeBinary(region, grid.raster());
    int best = grid.ny / 2, bestCount = -1;
    for (int j = 0; j < grid.ny; ++j) {
        int count = 0;
        for (int i = 0; i < grid.nx; ++i) count += inside[size_t(j) * grid.nx + i];
        if (count > bestCount) best = j, bestCount = count;
    }
    return best;
}

void SectionRecorder::write(const std::string& directory) const {
    writePng(directory + "/exposure_xz.png",
             outlinedMap(mSection, mSectionInside, mGrid.nx, mTotalSlices, mLaw));
    if (!mMap.empty())
        writePng(directory + "/exposure_xy.png",
                 outlinedMap(mMap, mMapInside, mGrid.nx, mGrid.ny, mLaw));
}

void writeDeviationFigures(const std::string& directory, const std::vector<glm::vec3>& cured,
                           const std::vector<float>& deviations) {
    if (deviations.empty()) return;
    float lo = *std::min_element(deviations.begin(), deviations.end());
    float hi = *std::max_element(deviations.begin(), deviations.end());
    double limit = std::max(1e-6, double(std::max(std::abs(lo), std::abs(hi))));
    const int bins = 60;
    PlotSeries histogram{"cured vertices", {}, {}, "#1f77b4", false};
    std::vector<double> counts(bins, 0.0);
    for (float d : deviations)
        counts[std::min(bins - 1, int((d + limit) / (2 * limit) * bins))] += 1;
    for (int b = 0; b < bins; ++b) {  // a step outline of the histogram
        double x0 = -limit + 2 * limit * b / bins, x1 = -limit + 2 * limit * (b + 1) / bins;
        histogram.x.insert(histogram.x.end(), {x0, x1});
        histogram.y.insert(histogram.y.end(), {counts[b], counts[b]});
    }
    writeSvgLinePlot(directory + "/deviation_histogram.svg",
                     "Signed deviation of the cured surface from the model",
                     "deviation (mm), positive = outside the model", "vertices", {histogram});

    // Deviation map: the cured surface seen from above; each pixel shows the vertex below it with
    // the largest |deviation|, blue (inside the model) - white - red (outside), dark where none.
    geometry::Bounds b;
    for (const auto& p : cured) b.add(glm::dvec3(p));
    const int width = 800;
    double scale = (width - 1) / std::max(1e-9, std::max(b.hi.x - b.lo.x, b.hi.y - b.lo.y));
    int w = int((b.hi.x - b.lo.x) * scale) + 1, h = int((b.hi.y - b.lo.y) * scale) + 1;
    std::vector<float> worst(size_t(w) * h, 0.0f);
    std::vector<uint8_t> seen(size_t(w) * h, 0);
    for (size_t v = 0; v < cured.size(); ++v) {
        const glm::dvec3 p(cured[v]);
        size_t index =
            size_t(h - 1 - int((p.y - b.lo.y) * scale)) * w + int((p.x - b.lo.x) * scale);
        if (!seen[index] || std::abs(deviations[v]) > std::abs(worst[index]))
            worst[index] = deviations[v];
        seen[index] = 1;
    }
    RgbImage image(w, h, 40);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t index = size_t(y) * w + x;
            if (!seen[index]) continue;
            double t = std::clamp(double(worst[index]) / limit, -1.0, 1.0);
            image.set(x, y, uint8_t(t > 0 ? 255 : 255 * (1 + t)), uint8_t(255 * (1 - std::abs(t))),
                      uint8_t(t < 0 ? 255 : 255 * (1 - t)));
        }
    writePng(directory + "/deviation_map_top.png", image);
}

void writeLayerErrorPlot(const std::string& path, const validate::SliceValidationSummary& summary) {
    PlotSeries error{"XY contour error", {}, {}, "", false};
    for (const auto& layer : summary.layers)
        if (layer.referencePerimeter > 0) {
            error.x.push_back(layer.z);
            error.y.push_back(layer.xyContourError() * 1000);
        }
    writeSvgLinePlot(path, "Cured vs model contour error per layer", "z (mm)", "mean XY error (um)",
                     {error});
}

}  // namespace vpsim::report
