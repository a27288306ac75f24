#include "vpsim/report/figures.h"

#include <algorithm>
#include <cmath>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/geometry/slicer.h"
#include "vpsim/plot/plot.h"
#include "vpsim/report/deviation_map.h"

namespace vpsim::report {
namespace {

/// An exposure map through the plotting layer: exposure in mJ/cm^2 from 0 to the 99th percentile
/// of what is shown (at least twice the critical dose), the model's outline (red) and the cured
/// outline (pink, dashed). `values` and `inside` are recorded with rows from the top.
void exposureFigure(const std::string& stem, const std::string& title, const std::string& yLabel,
                    const std::vector<float>& values, const std::vector<uint8_t>& inside, int width,
                    int height, double x0, double x1, double y0, double y1,
                    const cure::CureLaw& law) {
    plot::MapFigure f;
    f.title = title;
    f.yLabel = yLabel;
    f.nx = width, f.ny = height;
    f.x0 = x0, f.x1 = x1, f.y0 = y0, f.y1 = y1;
    f.values.resize(values.size());
    std::vector<float> model(values.size()), cured(values.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t from = size_t(height - 1 - y) * width + x, to = size_t(y) * width + x;
            f.values[to] = float(values[from] * 100.0);  // mJ/mm^2 -> mJ/cm^2
            model[to] = inside[from];
            cured[to] = law.isCured(values[from]) ? 1.0f : 0.0f;
        }
    std::vector<float> sorted(f.values);
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() * 99 / 100, sorted.end());
    const double top =
        std::max(2.0 * law.criticalDose() * 100, double(sorted[sorted.size() * 99 / 100]));
    size_t above = 0;
    for (float v : f.values) above += v > top;
    f.scale = {plot::ColourMap::Sequential, 0.0, top, "exposure (mJ/cm#u2#d)", false, above > 0};
    f.outlines.push_back({"model", model, 0.5, {230, 30, 30}, false});
    f.outlines.push_back(
        {"cured (critical dose " + formatNumber(law.criticalDose() * 100, 3) + " mJ/cm#u2#d)",
         cured,
         0.5,
         {255, 80, 200},
         true});
    f.note = formatNumber(100.0 * double(above) / double(f.values.size()), 2) +
             "% of the cells above the scale (drawn at its top)";
    plot::writeMapFigure(stem, f);
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

void SectionRecorder::saveState(BinaryStateWriter& out) const {
    out.add("sections.extent", std::vector<double>{double(mFilled), mTopZ, mBottomZ});
    out.add("sections.section", mSection);
    out.add("sections.section_inside", mSectionInside);
    out.add("sections.map", mMap);
    out.add("sections.map_inside", mMapInside);
}

void SectionRecorder::restoreState(const BinaryStateReader& in) {
    const std::vector<double> extent = in.take<double>("sections.extent", 3);
    if (!(extent[0] >= 0 && extent[0] <= mTotalSlices) || !std::isfinite(extent[1]) ||
        !std::isfinite(extent[2]))
        throw InputError("malformed checkpoint state (the sections' extent)", in.path());
    mFilled = int(extent[0]);
    mTopZ = extent[1];
    mBottomZ = extent[2];
    mSection = in.take<float>("sections.section", mSection.size());
    mSectionInside = in.take<uint8_t>("sections.section_inside", mSectionInside.size());
    mMap = in.take<float>("sections.map");  // empty until the map's layer is seen
    mMapInside = in.take<uint8_t>("sections.map_inside", mMap.size());
    if (!mMap.empty() && mMap.size() != size_t(mGrid.nx) * mGrid.ny)
        throw InputError("malformed checkpoint state (the section map is of another grid)",
                         in.path());
}

namespace {

/// The cells [i0, i1) x [j0, j1) of a row-major image `width` wide.
template <class T>
std::vector<T> windowOf(const std::vector<T>& whole, int width, int i0, int j0, int i1, int j1) {
    std::vector<T> window;
    for (int j = j0; j < j1; ++j)
        window.insert(window.end(), whole.begin() + ptrdiff_t(size_t(j) * width + i0),
                      whole.begin() + ptrdiff_t(size_t(j) * width + i1));
    return window;
}

/// Puts windowOf's cells back into `whole`.
template <class T>
void pasteWindow(std::vector<T>& whole, int width, const std::vector<T>& window, int i0, int j0,
                 int i1, int j1) {
    const size_t w = size_t(i1 - i0);
    for (int j = j0; j < j1; ++j)
        std::copy_n(window.begin() + ptrdiff_t(size_t(j - j0) * w), w,
                    whole.begin() + ptrdiff_t(size_t(j) * width + i0));
}

}  // namespace

void SectionRecorder::savePartial(BinaryStateWriter& out, const exposure::CellWindow& core) const {
    // The x-z section's columns of the core when the core holds its row; the x-y map's cells
    // of the core (image rows top-down) once its layer was seen.
    std::vector<float> section, map;
    std::vector<uint8_t> sectionInside, mapInside;
    if (mRow >= core.j0 && mRow < core.j1) {
        section = windowOf(mSection, mGrid.nx, core.i0, 0, core.i1, mTotalSlices);
        sectionInside = windowOf(mSectionInside, mGrid.nx, core.i0, 0, core.i1, mTotalSlices);
    }
    if (!mMap.empty()) {
        const int top = mGrid.ny - core.j1, bottom = mGrid.ny - core.j0;
        map = windowOf(mMap, mGrid.nx, core.i0, top, core.i1, bottom);
        mapInside = windowOf(mMapInside, mGrid.nx, core.i0, top, core.i1, bottom);
    }
    out.add("sections.extent", std::vector<double>{double(mFilled), mTopZ, mBottomZ});
    out.add("sections.tile_section", section);
    out.add("sections.tile_section_inside", sectionInside);
    out.add("sections.tile_map", map);
    out.add("sections.tile_map_inside", mapInside);
}

void SectionRecorder::mergePartial(const BinaryStateReader& in, const exposure::CellWindow& core) {
    const std::vector<double> extent = in.take<double>("sections.extent", 3);
    if (!(extent[0] >= 0 && extent[0] <= mTotalSlices) || !std::isfinite(extent[1]) ||
        !std::isfinite(extent[2]))
        throw InputError("malformed checkpoint state (the sections' extent)", in.path());
    if (int(extent[0]) >= mFilled) {  // every tile sees every slice: the same extent
        mFilled = int(extent[0]);
        mTopZ = extent[1];
        mBottomZ = extent[2];
    }
    const size_t width = size_t(core.width()), cells = width * size_t(core.height());
    const bool rowHere = mRow >= core.j0 && mRow < core.j1;
    const std::vector<float> section =
        in.take<float>("sections.tile_section", rowHere ? width * mTotalSlices : 0);
    const std::vector<uint8_t> sectionInside =
        in.take<uint8_t>("sections.tile_section_inside", section.size());
    const std::vector<float> map = in.take<float>("sections.tile_map");
    const std::vector<uint8_t> mapInside = in.take<uint8_t>("sections.tile_map_inside", map.size());
    if (!map.empty() && map.size() != cells)
        throw InputError("malformed checkpoint state (the section map is of another tile)",
                         in.path());
    if (rowHere) {
        pasteWindow(mSection, mGrid.nx, section, core.i0, 0, core.i1, mTotalSlices);
        pasteWindow(mSectionInside, mGrid.nx, sectionInside, core.i0, 0, core.i1, mTotalSlices);
    }
    if (!map.empty()) {
        if (mMap.empty()) {
            mMap.assign(size_t(mGrid.nx) * mGrid.ny, 0.0f);
            mMapInside.assign(mMap.size(), 0);
        }
        const int top = mGrid.ny - core.j1, bottom = mGrid.ny - core.j0;
        pasteWindow(mMap, mGrid.nx, map, core.i0, top, core.i1, bottom);
        pasteWindow(mMapInside, mGrid.nx, mapInside, core.i0, top, core.i1, bottom);
    }
}

void SectionRecorder::add(const exposure::ExposureSlice& slice) {
    // The slice's place from the top, whatever tile it belongs to: layers arrive top down.
    const int layers = mTotalSlices / mGrid.slicesPerLayer;
    const int index = (layers - 1 - slice.layer) * mGrid.slicesPerLayer + slice.slice;
    if (index < 0 || index >= mTotalSlices) return;
    if (index == 0) mTopZ = slice.z;
    if (index + 1 >= mFilled) mBottomZ = slice.z;  // the deepest so far
    mFilled = std::max(mFilled, index + 1);
    const exposure::CellWindow core = slice.owned();
    const exposure::SurfaceGrid& values = *slice.values;
    const bool rowHere = mRow >= core.j0 && mRow < core.j1;
    const bool mapHere = slice.layer == mMapLayer && slice.slice == mGrid.slicesPerLayer / 2;
    if (!rowHere && !mapHere) return;
    geometry::PolygonSet region = geometry::sliceAt(mPart, slice.z);
    if (rowHere)
        for (int i = core.i0; i < core.i1; ++i) {
            mSection[size_t(index) * mGrid.nx + i] =
                values.at(i - values.firstI, mRow - values.firstJ);
            mSectionInside[size_t(index) * mGrid.nx + i] = region.contains(
                {values.centreX(i - values.firstI), values.centreY(mRow - values.firstJ)});
        }
    if (mapHere) {  // image rows run top-down
        if (mMap.empty()) {
            mMap.assign(size_t(mGrid.nx) * mGrid.ny, 0.0f);
            mMapInside.assign(mMap.size(), 0);
        }
        const std::vector<uint8_t> inside = geometry::rasterizeBinary(
            region, mGrid.raster(), core.i0, core.j0, core.width(), core.height());
        for (int j = core.j0; j < core.j1; ++j)
            for (int i = core.i0; i < core.i1; ++i) {
                const size_t image = size_t(mGrid.ny - 1 - j) * mGrid.nx + i;
                mMap[image] = values.at(i - values.firstI, j - values.firstJ);
                mMapInside[image] = inside[size_t(j - core.j0) * core.width() + (i - core.i0)];
            }
    }
}

int busiestRow(const std::vector<geometry::PolygonSet>& regions,
               const exposure::ExposureGrid& grid) {
    // Material per row summed over every layer: the cut through the most of the part, not of
    // one layer (the middle layer of an overhang part may be only its pillars).
    std::vector<long> counts(grid.ny, 0), layerCounts(grid.ny, 0);
    std::vector<geometry::Contour> previous;
    for (size_t k = 0; k < regions.size(); ++k) {
        std::vector<geometry::Contour> contours = regions[k].contours();
        if (k == 0 || contours != previous) {  // a prism's layers: one cross-section, counted once
            const std::vector<uint8_t> inside =
                geometry::rasterizeBinary(regions[k], grid.raster());
            for (int j = 0; j < grid.ny; ++j)
                layerCounts[j] = std::count(inside.begin() + ptrdiff_t(j) * grid.nx,
                                            inside.begin() + ptrdiff_t(j + 1) * grid.nx, 1);
            previous = std::move(contours);
        }
        for (int j = 0; j < grid.ny; ++j) counts[j] += layerCounts[j];
    }
    // The middle of the rows that cross the most material, not the first of them (which lies at
    // the part's edge when many rows tie, as in a box or the foot of an L).
    const long most = grid.ny > 0 ? *std::max_element(counts.begin(), counts.end()) : 0;
    std::vector<int> busiest;
    for (int j = 0; j < grid.ny; ++j)
        if (counts[j] == most) busiest.push_back(j);
    return busiest.empty() ? grid.ny / 2 : busiest[busiest.size() / 2];
}

void SectionRecorder::write(const std::string& directory) const {
    const double x0 = mGrid.originX, x1 = x0 + mGrid.nx * mGrid.pitch;
    const double dz = mFilled > 1 ? (mTopZ - mBottomZ) / (mFilled - 1) : mGrid.pitch;
    const double rowY = mGrid.originY + (mRow + 0.5) * mGrid.pitch;
    std::vector<float> section(mSection.begin(), mSection.begin() + size_t(mFilled) * mGrid.nx);
    std::vector<uint8_t> inside(mSectionInside.begin(),
                                mSectionInside.begin() + size_t(mFilled) * mGrid.nx);
    if (mFilled > 0)
        exposureFigure(directory + "/exposure_xz",
                       "x-z section at y = " + formatNumber(rowY, 4) + " mm", "z (mm)", section,
                       inside, mGrid.nx, mFilled, x0, x1, mBottomZ - dz / 2, mTopZ + dz / 2, mLaw);
    if (!mMap.empty())
        exposureFigure(directory + "/exposure_xy",
                       "x-y exposure of layer " + std::to_string(mMapLayer + 1) + ", mid-layer",
                       "y (mm)", mMap, mMapInside, mGrid.nx, mGrid.ny, x0, x1, mGrid.originY,
                       mGrid.originY + mGrid.ny * mGrid.pitch, mLaw);
}

void writeLayerErrorPlot(const std::string& stem, const validate::SliceValidationSummary& summary) {
    plot::Curve error;
    for (const auto& layer : summary.layers)
        if (layer.referencePerimeter > 0) {
            error.x.push_back(layer.z);
            error.y.push_back(layer.xyContourError() * 1000);
        }
    plot::LineFigure f;
    f.title = "Cured against model contour error per layer";
    f.xLabel = "z (mm)";
    f.yLabel = "mean XY error (µm)";
    f.curves.push_back(error);
    plot::writeLineFigure(stem, f);
}

}  // namespace vpsim::report
