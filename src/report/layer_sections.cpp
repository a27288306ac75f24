#include "vpsim/report/layer_sections.h"

#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "section_view_js.h"  // generated from assets/section_view.js: SECTION_VIEW_JS
#include "vpsim/core/image.h"
#include "vpsim/core/io.h"
#include "vpsim/core/text.h"
#include "vpsim/report/viewer3d.h"

namespace vpsim::report {
namespace {

int ceilDiv(int a, int b) {
    return (a + b - 1) / b;
}

/// The model's outline of each kept layer as [contours, points of each contour...] counts and
/// x, y pairs (mm), vertices closer than `step` to the last one kept dropped (the view's pixels
/// cannot show them).
void outlines(const geometry::LayerStack& stack, const std::vector<int>& kept, double step,
              std::vector<uint32_t>& counts, std::vector<float>& xy) {
    for (int layer : kept) {
        if (layer >= int(stack.layers.size())) {
            counts.push_back(0);
            continue;
        }
        const std::vector<geometry::Contour> contours = stack.layers[layer].region.contours();
        counts.push_back(uint32_t(contours.size()));
        for (const geometry::Contour& c : contours) {
            uint32_t n = 0;
            glm::dvec2 last{};
            for (size_t i = 0; i < c.size(); ++i) {
                if (i > 0 && c.size() - i > 2 && glm::length(c[i] - last) < step) continue;
                xy.push_back(float(c[i].x)), xy.push_back(float(c[i].y));
                last = c[i];
                ++n;
            }
            counts.push_back(n);
        }
    }
}

/// window.VPSIM_KERNEL's fields: the table I(r, z) and the Eq. 12 fit on the same bin centres.
std::string kernelJs(const kernel::BeamKernel& k) {
    std::vector<float> fit(size_t(k.rBins) * k.zBins);
    for (uint32_t iz = 0; iz < k.zBins; ++iz)
        for (uint32_t ir = 0; ir < k.rBins; ++ir)
            fit[size_t(iz) * k.rBins + ir] =
                float(k.fitted((ir + 0.5) * k.rBin, (iz + 0.5) * k.zBin));
    return "{\"r_bins\":" + std::to_string(k.rBins) + ",\"z_bins\":" + std::to_string(k.zBins) +
           ",\"r_bin_um\":" + formatNumber(k.rBin * 1000, 6) +
           ",\"z_bin_um\":" + formatNumber(k.zBin * 1000, 6) + ",\"intensity\":\"" +
           base64Of(k.intensity) + "\",\"fit\":\"" + base64Of(fit) +
           "\",\"we3d_um\":" + formatNumber(k.fit.we3d * 1000, 4) +
           ",\"de3d_um\":" + formatNumber(k.fit.de3d * 1000, 4) +
           ",\"fit_depth_start_um\":" + formatNumber(k.fit.fitDepthStart * 1000, 4) +
           ",\"residual\":" + formatNumber(k.fit.residual, 4) +
           ",\"photons\":" + std::to_string(k.photons) + "}";
}

}  // namespace

SectionSampling sectionSampling(int nx, int ny, int layers) {
    SectionSampling s;
    const int longSide = std::max({nx, ny, 1});
    const auto pixels = [&](int factor) {
        return uint64_t(ceilDiv(nx, factor)) * uint64_t(ceilDiv(ny, factor));
    };
    s.factor = std::max(1, ceilDiv(longSide, SECTION_MAX_SIDE));
    const int coarsest = std::max(s.factor, ceilDiv(longSide, SECTION_MIN_SIDE));
    while (s.factor < coarsest && pixels(s.factor) * uint64_t(layers) > SECTION_PIXEL_BUDGET)
        ++s.factor;
    s.width = ceilDiv(nx, s.factor);
    s.height = ceilDiv(ny, s.factor);
    const uint64_t perLayer = std::max<uint64_t>(1, pixels(s.factor));
    s.stride = int(std::max<uint64_t>(
        1, (uint64_t(layers) * perLayer + SECTION_PIXEL_BUDGET - 1) / SECTION_PIXEL_BUDGET));
    return s;
}

uint64_t layerSectionBytes(int nx, int ny, int layers) {
    const SectionSampling s = sectionSampling(nx, ny, layers);
    const uint64_t kept = uint64_t(ceilDiv(layers, s.stride)) + 1;
    return kept * uint64_t(s.width) * uint64_t(s.height) * 8;  // float sum, cured count
}

LayerSectionRecorder::LayerSectionRecorder(const geometry::LayerStack& stack,
                                           const exposure::ExposureGrid& grid,
                                           const cure::CureLaw& law)
    : mStack(stack), mGrid(grid), mLaw(law) {
    const int layers = int(stack.layers.size());
    mSampling = sectionSampling(grid.nx, grid.ny, layers);
    mSlot.assign(size_t(layers), -1);
    for (int k = 0; k < layers; ++k)
        if (k % mSampling.stride == 0 || k == layers - 1) {
            mSlot[k] = int(mKept.size());
            mKept.push_back(k);
        }
    const size_t cells = mKept.size() * size_t(mSampling.width) * size_t(mSampling.height);
    mExposure.assign(cells, 0.0f);
    mCured.assign(cells, 0);
    mZ.assign(mKept.size(), 0.0);
}

void LayerSectionRecorder::saveState(BinaryStateWriter& out) const {
    out.add("layer_sections.z", mZ);
    out.add("layer_sections.exposure", mExposure);
    out.add("layer_sections.cured", mCured);
}

void LayerSectionRecorder::restoreState(const BinaryStateReader& in) {
    mZ = in.take<double>("layer_sections.z", mZ.size());
    mExposure = in.take<float>("layer_sections.exposure", mExposure.size());
    mCured = in.take<uint32_t>("layer_sections.cured", mCured.size());
}

void LayerSectionRecorder::add(const exposure::ExposureSlice& slice) {
    if (slice.slice != mGrid.slicesPerLayer / 2) return;  // the layer's middle voxel slice
    if (slice.layer < 0 || slice.layer >= int(mSlot.size()) || mSlot[slice.layer] < 0) return;
    const int slot = mSlot[slice.layer];
    mZ[slot] = slice.z;
    // Sums over the cells this slice owns, in whole-grid cells: a tiled run adds each tile's
    // share of a pixel's block, summed from zero (a rank's tile alone sums the same), to the
    // pixel's sum; write() divides by the block's cell count.
    const exposure::SurfaceGrid& values = *slice.values;
    const exposure::CellWindow owned = slice.owned();
    const int f = mSampling.factor, w = mSampling.width;
    const size_t base = size_t(slot) * w * mSampling.height;
    const float curedAt = mLaw.curedFloatThreshold();  // v >= curedAt: isCured(v), exactly
    const int p0 = owned.i0 / f, p1 = (owned.i1 - 1) / f + 1;
    // Rows of pixels in parallel: each pixel's sum is made by one task, in its cells' order.
    tbb::parallel_for(owned.j0 / f, (owned.j1 - 1) / f + 1, [&](int pj) {
        std::vector<float> share(size_t(p1 - p0), 0.0f);
        auto* cured = &mCured[base + size_t(pj) * w];
        for (int j = std::max(owned.j0, pj * f); j < std::min(owned.j1, (pj + 1) * f); ++j) {
            const float* row = &values.values[size_t(j - values.firstJ) * values.nx];
            // The pixels' blocks of f cells in turn: each pixel's sum in the order of its cells.
            for (int i0 = owned.i0; i0 < owned.i1;) {
                const int pixel = i0 / f, i1 = std::min(owned.i1, (pixel + 1) * f);
                float sum = share[pixel - p0];
                int count = 0;
                for (int i = i0; i < i1; ++i) {
                    const float v = row[i - values.firstI];
                    sum += v;
                    count += v >= curedAt;
                }
                share[pixel - p0] = sum;
                cured[pixel] += count;
                i0 = i1;
            }
        }
        float* exposure = &mExposure[base + size_t(pj) * w];
        for (int pixel = p0; pixel < p1; ++pixel) exposure[pixel] += share[pixel - p0];
    });
}

std::array<int, 4> LayerSectionRecorder::pixelWindow(const exposure::CellWindow& core) const {
    const int f = mSampling.factor;
    if (core.i1 <= core.i0 || core.j1 <= core.j0) return {0, 0, 0, 0};
    return {core.i0 / f, core.j0 / f, (core.i1 - 1) / f + 1, (core.j1 - 1) / f + 1};
}

void LayerSectionRecorder::savePartial(BinaryStateWriter& out,
                                       const exposure::CellWindow& core) const {
    const auto [x0, y0, x1, y1] = pixelWindow(core);
    const int w = mSampling.width, h = mSampling.height;
    std::vector<float> exposure;
    std::vector<uint32_t> cured;
    for (size_t slot = 0; slot < mKept.size(); ++slot)
        for (int y = y0; y < y1; ++y) {
            const size_t at = (slot * h + size_t(y)) * w;
            exposure.insert(exposure.end(), mExposure.begin() + ptrdiff_t(at + x0),
                            mExposure.begin() + ptrdiff_t(at + x1));
            cured.insert(cured.end(), mCured.begin() + ptrdiff_t(at + x0),
                         mCured.begin() + ptrdiff_t(at + x1));
        }
    out.add("layer_sections.z", mZ);
    out.add("layer_sections.tile_exposure", exposure);
    out.add("layer_sections.tile_cured", cured);
}

void LayerSectionRecorder::mergePartial(const BinaryStateReader& in,
                                        const exposure::CellWindow& core) {
    const auto [x0, y0, x1, y1] = pixelWindow(core);
    const int w = mSampling.width, h = mSampling.height;
    const size_t cells = mKept.size() * size_t(y1 - y0) * size_t(x1 - x0);
    mZ = in.take<double>("layer_sections.z", mZ.size());
    const auto exposure = in.take<float>("layer_sections.tile_exposure", cells);
    const auto cured = in.take<uint32_t>("layer_sections.tile_cured", cells);
    size_t from = 0;
    for (size_t slot = 0; slot < mKept.size(); ++slot)
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x, ++from) {
                const size_t at = (slot * h + size_t(y)) * w + size_t(x);
                mExposure[at] += exposure[from];
                mCured[at] += cured[from];
            }
}

std::vector<float> LayerSectionRecorder::blockCells() const {
    const int f = mSampling.factor, w = mSampling.width, h = mSampling.height;
    std::vector<float> cells(size_t(w) * h);
    for (int pj = 0; pj < h; ++pj)
        for (int pi = 0; pi < w; ++pi)
            cells[size_t(pj) * w + pi] =
                float(std::min(f, mGrid.nx - pi * f) * std::min(f, mGrid.ny - pj * f));
    return cells;
}

SectionViewSummary LayerSectionRecorder::write(const std::string& outDir,
                                               const kernel::BeamKernel* kernel) const {
    SectionViewSummary s;
    s.layers = int(mSlot.size());
    s.layersKept = int(mKept.size());
    s.width = mSampling.width;
    s.height = mSampling.height;
    s.pixelMm = mGrid.pitch * mSampling.factor;
    // Block means and the majority rule from the sums add() gathered.
    const std::vector<float> cellsPerPixel = blockCells();
    std::vector<float> exposure(mExposure.size());
    std::vector<uint8_t> curedPixel(mExposure.size());
    for (size_t p = 0; p < exposure.size(); ++p) {
        const float cells = cellsPerPixel[p % cellsPerPixel.size()];
        exposure[p] = mExposure[p] / cells;
        curedPixel[p] = 2.0f * float(mCured[p]) >= cells;
    }
    // One linear scale for every layer, as the exposure figures choose theirs (mJ/cm^2).
    const double critical = mLaw.criticalDose() * 100;
    std::vector<float> sample;
    const size_t step = std::max<size_t>(1, exposure.size() / (1u << 20));
    for (size_t i = 0; i < exposure.size(); i += step) sample.push_back(exposure[i] * 100.0f);
    double top = 2 * critical;
    if (!sample.empty()) {
        std::nth_element(sample.begin(), sample.begin() + sample.size() * 99 / 100, sample.end());
        top = std::max(top, double(sample[sample.size() * 99 / 100]));
    }
    s.scaleMax = top;
    std::vector<uint8_t> quantised(exposure.size());
    std::vector<uint8_t> curedBits;
    const size_t perLayer = size_t(s.width) * s.height, bytesPerLayer = (perLayer + 7) / 8;
    curedBits.assign(mKept.size() * bytesPerLayer, 0);
    size_t above = 0;
    for (size_t i = 0; i < exposure.size(); ++i) {
        const double t = exposure[i] * 100.0 / top;
        above += t > 1;
        quantised[i] = uint8_t(std::lround(std::clamp(t, 0.0, 1.0) * 255));
        const size_t layer = i / perLayer, bit = i % perLayer;
        if (curedPixel[i]) curedBits[layer * bytesPerLayer + bit / 8] |= uint8_t(1u << (bit % 8));
    }
    s.aboveScale = exposure.empty() ? 0.0 : double(above) / double(exposure.size());
    std::vector<uint32_t> counts;
    std::vector<float> xy;
    outlines(mStack, mKept, s.pixelMm / 2, counts, xy);
    std::vector<uint8_t> palette(256 * 3);
    for (int k = 0; k < 256; ++k)
        viridis(k / 255.0, palette[3 * k], palette[3 * k + 1], palette[3 * k + 2]);
    std::string zs = "[";
    for (size_t i = 0; i < mZ.size(); ++i) zs += (i ? "," : "") + formatNumber(mZ[i], 6);
    std::string keptText = "[";
    for (size_t i = 0; i < mKept.size(); ++i) keptText += (i ? "," : "") + std::to_string(mKept[i]);
    std::string js =
        "window.VPSIM_SECTIONS={\"width\":" + std::to_string(s.width) +
        ",\"height\":" + std::to_string(s.height) + ",\"x0\":" + formatNumber(mGrid.originX, 6) +
        ",\"y0\":" + formatNumber(mGrid.originY, 6) +
        ",\"pixel_mm\":" + formatNumber(s.pixelMm, 6) + ",\"scale_max\":" + formatNumber(top, 9) +
        ",\"critical\":" + formatNumber(critical, 4) +
        ",\"above_fraction\":" + formatNumber(s.aboveScale, 4) +
        ",\"layers\":" + std::to_string(s.layers) + ",\"kept\":" + keptText + "],\"z\":" + zs +
        "],\"exposure\":\"" + base64Of(quantised) + "\",\"cured\":\"" + base64Of(curedBits) +
        "\",\"outline_counts\":\"" + base64Of(counts) + "\",\"outline_xy\":\"" + base64Of(xy) +
        "\",\"palette\":\"" + base64Of(palette) +
        "\"};\nwindow.VPSIM_KERNEL=" + (kernel ? kernelJs(*kernel) : std::string("null")) + ";\n";
    s.kernel = kernel != nullptr;
    s.dataBytes = js.size();
    writeFileAtomic(outDir + "/sections.js", js);
    writeFileAtomic(outDir + "/section_view.js", SECTION_VIEW_JS);
    return s;
}

}  // namespace vpsim::report
