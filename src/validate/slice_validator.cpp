#include "vpsim/validate/slice_validator.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <nlohmann/json.hpp>

#include "exposure/avx2_clones.h"
#include "vpsim/core/error.h"
#include "vpsim/geometry/raster.h"
#include "vpsim/geometry/slicer.h"

namespace vpsim::validate {

double LayerComparison::xyContourError() const {
    if (referencePerimeter <= 0) return 0.0;
    double symmetricDifference = referenceArea + curedArea - 2 * intersectionArea;
    return symmetricDifference / referencePerimeter;
}

namespace {

/// One row's counts, summed in row order after the rows' parallel loop.
struct RowCounts {
    uint64_t inter = 0, cured = 0, reference = 0, unionCount = 0, exposed = 0;
    long downFacing = 0;
    float maxDose = 0;
};

/// One row's voxel counts, written so the compiler vectorises it: integer sums of 0/1 flags,
/// and the maximum taken on the float bits (the same order as the floats for doses >= 0; the
/// maximum starts at 0, so negative doses, which the engines never give, leave it as before).
/// Built for AVX2 too (chosen at run time): integer counts and an exact maximum, so the same.
VPSIM_AVX2_CLONES void countRow(const float* dose, const uint8_t* reference, int n, float curedAt,
                                float storeLevel, RowCounts& row) {
    uint32_t inter = 0, cured = 0, ref = 0, unionCount = 0, exposed = 0;
    int32_t maxBits = 0;
    for (int i = 0; i < n; ++i) {
        const float d = dose[i];
        const uint32_t r = reference[i] != 0, cu = d >= curedAt;
        int32_t bits;
        std::memcpy(&bits, &d, sizeof bits);
        maxBits = std::max(maxBits, bits);
        exposed += d > storeLevel;
        inter += r & cu;
        cured += cu;
        ref += r;
        unionCount += r | cu;
    }
    float maxDose;
    std::memcpy(&maxDose, &maxBits, sizeof maxDose);
    row.maxDose = std::max(row.maxDose, maxDose);
    row.inter += inter, row.cured += cured, row.reference += ref;
    row.unionCount += unionCount, row.exposed += exposed;
}

/// Whether any of n cells carries a run or lies just under the reference's bottom (flags 0/1):
/// most rows have none (a row of the part's inside or outside), and this loop is vectorised.
VPSIM_AVX2_CLONES bool anyRunCell(const uint8_t* __restrict inRun, const uint8_t* __restrict above,
                                  const uint8_t* __restrict reference, int n) {
    uint8_t any = 0;
    for (int i = 0; i < n; ++i) any |= inRun[i] | (above[i] & ~reference[i]);
    return any != 0;
}

/// Whether any of 8 cells carries a run or lies just under the reference's bottom.
bool anyRunCell8(const uint8_t* inRun, const uint8_t* above, const uint8_t* reference) {
    uint64_t run, a, r;
    std::memcpy(&run, inRun, 8);
    std::memcpy(&a, above, 8);
    std::memcpy(&r, reference, 8);
    return (run | (a & ~r)) != 0;
}

}  // namespace

/// One layer's mid-plane counts, summed over the tiles.
struct LayerCounts {
    double z = 0, perimeter = 0;
    uint64_t reference = 0, cured = 0, intersection = 0;
};

struct SliceValidator::State {
    const geometry::Mesh& part;
    exposure::ExposureGrid grid;
    const cure::CureLaw& law;
    double voxelHeight;
    geometry::RasterGrid raster;
    // Per column of the current tile's core (the whole grid when untiled):
    exposure::CellWindow core;
    std::vector<uint8_t> referenceAbove;  ///< reference solid in the slice above, per column
    std::vector<uint8_t> inRun;           ///< column is in cured resin directly below the reference
    std::vector<float> run;               ///< depth of that run so far (mm)
    uint64_t intersection = 0, unionCount = 0, cured = 0, reference = 0;
    std::vector<float> runs;  ///< finished over-cure runs (mm), one per down-facing column event
    long downFacing = 0;
    uint64_t exposed = 0;
    double maxDose = 0;
    std::mutex runsMutex;
    std::map<int, LayerCounts> layers;  ///< by layer index, bottom first

    // The last rasterised cross-section: a prismatic stretch of the part (every slice of a box)
    // has the same contours slice after slice, and rasterizeBinary depends on nothing else.
    std::vector<geometry::Contour> rasterContours;
    exposure::CellWindow rasterWindow{0, 0, -1, -1};
    std::vector<uint8_t> rasterCells;

    const std::vector<uint8_t>& rasterOf(const geometry::PolygonSet& region,
                                         const exposure::CellWindow& w) {
        std::vector<geometry::Contour> contours = region.contours();
        const bool sameWindow = w.i0 == rasterWindow.i0 && w.j0 == rasterWindow.j0 &&
                                w.i1 == rasterWindow.i1 && w.j1 == rasterWindow.j1;
        if (!sameWindow || contours != rasterContours) {
            rasterCells =
                geometry::rasterizeBinary(region, raster, w.i0, w.j0, w.width(), w.height());
            rasterContours = std::move(contours);
            rasterWindow = w;
        }
        return rasterCells;
    }

    State(const geometry::Mesh& mesh, const exposure::ExposureGrid& g, const cure::CureLaw& l,
          double dz)
        : part(mesh), grid(g), law(l), voxelHeight(dz), raster(g.raster()) {}

    /// Columns for a tile's core: the runs still open in the previous tile reach its bottom.
    void startTile(const exposure::CellWindow& w) {
        finishOpenRuns();
        core = w;
        const size_t cells = size_t(w.width()) * w.height();
        referenceAbove.assign(cells, 0);
        inRun.assign(cells, 0);
        run.assign(cells, 0.0f);
    }

    void finishOpenRuns() {
        for (size_t c = 0; c < inRun.size(); ++c)
            if (inRun[c]) {
                runs.push_back(run[c]);
                inRun[c] = 0;
                run[c] = 0;
            }
    }
};

SliceValidator::SliceValidator(const geometry::Mesh& part, const exposure::ExposureGrid& grid,
                               const cure::CureLaw& law, double voxelHeight)
    : mState(std::make_unique<State>(part, grid, law, voxelHeight)) {
    if (!(voxelHeight > 0)) throw InputError("validation needs a positive voxel height");
}

SliceValidator::~SliceValidator() = default;

void SliceValidator::add(const exposure::ExposureSlice& slice) {
    State& s = *mState;
    const exposure::SurfaceGrid& values = *slice.values;
    const exposure::CellWindow w = slice.owned();
    if (w.i0 < values.firstI || w.j0 < values.firstJ || w.i1 > values.firstI + values.nx ||
        w.j1 > values.firstJ + values.ny || w.i1 > s.grid.nx || w.j1 > s.grid.ny)
        throw ResourceError("exposure slice does not match the validation grid");
    if (w.i0 != s.core.i0 || w.j0 != s.core.j0 || w.i1 != s.core.i1 || w.j1 != s.core.j1)
        s.startTile(w);
    geometry::PolygonSet region = geometry::sliceAt(s.part, slice.z);
    const std::vector<uint8_t>& reference = s.rasterOf(region, w);
    // Rows in parallel, each with its own counts, added in row order afterwards; the finished
    // over-cure runs are only sorted and summed in order later, so nothing depends on threads
    // (or on the tiles: counts are integers, the maximum is exact, the runs are sorted).
    const int nx = w.width(), ny = w.height();
    const float curedAt = s.law.curedFloatThreshold();  // d >= curedAt: isCured(d), exactly
    const float storeLevel = float(0.02 * s.law.criticalDose());  // as the DoseVolume keeps
    const float dz = float(s.voxelHeight);
    std::vector<RowCounts> rows(ny);
    tbb::parallel_for(tbb::blocked_range<int>(0, ny, 8), [&](const tbb::blocked_range<int>& range) {
        std::vector<float> finished;
        for (int j = range.begin(); j < range.end(); ++j) {
            RowCounts& row = rows[j];
            const float* dose = &values.values[size_t(j + w.j0 - values.firstJ) * values.nx +
                                               size_t(w.i0 - values.firstI)];
            const size_t first = size_t(j) * nx;
            const uint8_t* ref = &reference[first];
            countRow(dose, ref, nx, curedAt, storeLevel, row);
            // The over-cure runs: only cells that carry a run or sit just under the reference's
            // bottom (few; in rows that have any), found eight at a time.
            uint8_t* inRun = &s.inRun[first];
            const uint8_t* above = &s.referenceAbove[first];
            float* run = &s.run[first];
            const bool anyRun = anyRunCell(inRun, above, ref, nx);
            for (int i = 0; anyRun && i < nx; ++i) {
                if (i % 8 == 0 && i + 8 <= nx && !anyRunCell8(inRun + i, above + i, ref + i)) {
                    i += 7;
                    continue;
                }
                const bool r = ref[i] != 0;
                if (!(inRun[i] | (above[i] & !r))) continue;
                if (r) {
                    finished.push_back(run[i]), inRun[i] = 0, run[i] = 0;
                } else {
                    if (above[i]) {  // the reference's down-facing surface is above
                        ++row.downFacing;
                        inRun[i] = 1;
                        run[i] = 0;
                    }
                    if (dose[i] >= curedAt)
                        run[i] += dz;
                    else
                        finished.push_back(run[i]), inRun[i] = 0, run[i] = 0;
                }
            }
            // referenceAbove becomes this slice's reference (copied after the row's cells).
            std::memcpy(&s.referenceAbove[first], ref, nx);
        }
        if (!finished.empty()) {
            std::lock_guard<std::mutex> lock(s.runsMutex);
            s.runs.insert(s.runs.end(), finished.begin(), finished.end());
        }
    });
    uint64_t inter = 0, curedHere = 0, referenceHere = 0;
    for (const RowCounts& row : rows) {
        inter += row.inter;
        curedHere += row.cured;
        referenceHere += row.reference;
        s.unionCount += row.unionCount;
        s.exposed += row.exposed;
        s.downFacing += row.downFacing;
        s.maxDose = std::max(s.maxDose, double(row.maxDose));
    }
    s.intersection += inter;
    s.cured += curedHere;
    s.reference += referenceHere;
    if (slice.slice == s.grid.slicesPerLayer / 2) {
        auto [layer, first] = s.layers.try_emplace(slice.layer);
        if (first) {
            layer->second.z = slice.z;
            layer->second.perimeter = region.perimeter();
        }
        layer->second.reference += referenceHere;
        layer->second.cured += curedHere;
        layer->second.intersection += inter;
    }
}

SliceValidationSummary SliceValidator::summary() const {
    State& s = *mState;
    s.finishOpenRuns();  // runs reaching the bottom of the simulated volume
    SliceValidationSummary out;
    const double voxelVolume = s.grid.pitch * s.grid.pitch * s.voxelHeight;
    out.iou = s.unionCount ? double(s.intersection) / double(s.unionCount) : 0.0;
    out.curedVolume = double(s.cured) * voxelVolume;
    out.referenceVolume = double(s.reference) * voxelVolume;
    out.downFacingColumns = s.downFacing;
    out.maxDose = s.maxDose;
    out.exposedVoxels = s.exposed;
    if (!s.runs.empty()) {
        std::vector<float> runs = s.runs;
        std::sort(runs.begin(), runs.end());
        double sum = 0;
        for (float r : runs) sum += r;
        out.overcureBelowDownFacingMean = sum / double(runs.size());
        out.overcureBelowDownFacingMedian = runs[runs.size() / 2];
        out.overcureBelowDownFacingMax = runs.back();
    }
    const double cellArea = s.grid.pitch * s.grid.pitch;
    for (const auto& [index, counts] : s.layers) {
        LayerComparison layer;
        layer.layer = index;
        layer.z = counts.z;
        layer.referenceArea = double(counts.reference) * cellArea;
        layer.curedArea = double(counts.cured) * cellArea;
        layer.intersectionArea = double(counts.intersection) * cellArea;
        layer.referencePerimeter = counts.perimeter;
        out.layers.push_back(layer);
    }
    int counted = 0;
    for (const auto& layer : out.layers)
        if (layer.referencePerimeter > 0) {
            out.xyContourErrorMean += layer.xyContourError();
            out.xyContourErrorMax = std::max(out.xyContourErrorMax, layer.xyContourError());
            ++counted;
        }
    if (counted) out.xyContourErrorMean /= counted;
    return out;
}

namespace {

/// Over-cure runs as [length, how many] in increasing length: a run is a sum of voxel heights,
/// so there are few distinct lengths (a state's size follows the height, not the footprint);
/// summary() sorts the runs, so their order is no figure.
nlohmann::json runCounts(const std::vector<float>& runs) {
    std::map<float, uint64_t> counts;
    for (float r : runs) ++counts[r];
    nlohmann::json out = nlohmann::json::array();
    for (const auto& [length, n] : counts) out.push_back({length, n});
    return out;
}

void appendRuns(const nlohmann::json& counts, std::vector<float>& runs) {
    for (const auto& entry : counts)
        runs.insert(runs.end(), entry.at(1).get<uint64_t>(), entry.at(0).get<float>());
}

}  // namespace

nlohmann::json SliceValidator::saveState() {
    State& s = *mState;
    s.finishOpenRuns();  // as the next tile's start does
    nlohmann::json layers = nlohmann::json::array();
    for (const auto& [index, c] : s.layers)
        layers.push_back({index, c.z, c.perimeter, c.reference, c.cured, c.intersection});
    return {{"intersection", s.intersection},
            {"union", s.unionCount},
            {"cured", s.cured},
            {"reference", s.reference},
            {"runs", runCounts(s.runs)},
            {"down_facing", s.downFacing},
            {"exposed", s.exposed},
            {"max_dose", s.maxDose},
            {"layers", layers}};
}

void SliceValidator::restoreState(const nlohmann::json& state) {
    State& s = *mState;
    try {
        s.intersection = state.at("intersection").get<uint64_t>();
        s.unionCount = state.at("union").get<uint64_t>();
        s.cured = state.at("cured").get<uint64_t>();
        s.reference = state.at("reference").get<uint64_t>();
        s.runs.clear();
        appendRuns(state.at("runs"), s.runs);
        s.downFacing = state.at("down_facing").get<long>();
        s.exposed = state.at("exposed").get<uint64_t>();
        s.maxDose = state.at("max_dose").get<double>();
        s.layers.clear();
        for (const auto& l : state.at("layers"))
            s.layers[l.at(0).get<int>()] = {l.at(1).get<double>(), l.at(2).get<double>(),
                                            l.at(3).get<uint64_t>(), l.at(4).get<uint64_t>(),
                                            l.at(5).get<uint64_t>()};
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed slice-validation state: ") + e.what());
    }
}

void SliceValidator::mergeState(const nlohmann::json& later) {
    State& s = *mState;
    s.finishOpenRuns();
    try {
        s.intersection += later.at("intersection").get<uint64_t>();
        s.unionCount += later.at("union").get<uint64_t>();
        s.cured += later.at("cured").get<uint64_t>();
        s.reference += later.at("reference").get<uint64_t>();
        appendRuns(later.at("runs"), s.runs);
        s.downFacing += later.at("down_facing").get<long>();
        s.exposed += later.at("exposed").get<uint64_t>();
        s.maxDose = std::max(s.maxDose, later.at("max_dose").get<double>());
        for (const auto& l : later.at("layers")) {
            auto [layer, first] = s.layers.try_emplace(l.at(0).get<int>());
            if (first) {  // as add() sets them: from the layer's first tile
                layer->second.z = l.at(1).get<double>();
                layer->second.perimeter = l.at(2).get<double>();
            }
            layer->second.reference += l.at(3).get<uint64_t>();
            layer->second.cured += l.at(4).get<uint64_t>();
            layer->second.intersection += l.at(5).get<uint64_t>();
        }
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed slice-validation state: ") + e.what());
    }
}

nlohmann::json SliceValidationSummary::toJson() const {
    nlohmann::json perLayer = nlohmann::json::array();
    for (const auto& l : layers)
        perLayer.push_back({{"layer", l.layer},
                            {"z", l.z},
                            {"reference_area_mm2", l.referenceArea},
                            {"cured_area_mm2", l.curedArea},
                            {"xy_contour_error_mm", l.xyContourError()}});
    return {{"iou", iou},
            {"cured_volume_mm3", curedVolume},
            {"reference_volume_mm3", referenceVolume},
            {"overcure_below_downfacing_mm",
             {{"median", overcureBelowDownFacingMedian},
              {"max", overcureBelowDownFacingMax},
              {"mean", overcureBelowDownFacingMean},
              {"columns", downFacingColumns}}},
            {"xy_contour_error_mm", {{"mean", xyContourErrorMean}, {"max", xyContourErrorMax}}},
            {"layers", perLayer}};
}

}  // namespace vpsim::validate
