#include "vpsim/optimise/laser/exposure_error_sink.h"

#include <optional>

#include "vpsim/core/error.h"

#include "exposure_error_sum.h"

namespace vpsim::optimise {

struct ExposureErrorSink::State {
    exposure::ExposureGrid grid;
    std::vector<geometry::PolygonSet> regions;
    std::vector<std::optional<geometry::PolygonSet>> counted;  ///< regions grown by the band
    double targetDose, band, surfaceScale;
    int topLayer = -1;
    std::vector<ExposureError> errors;  ///< per layer, the sums of the tiles seen
    detail::ErrorHistogram histogram;
    exposure::SurfaceGrid topMap;
    /// The last layer's masks (inside its region; counted: within the band) and what they were
    /// made for: the next layer of the same region in the same window (a prism's) reuses them.
    std::vector<char> inside, countedCells;
    std::vector<geometry::Contour> maskContours;
    exposure::CellWindow maskWindow{0, 0, -1, -1};

    const geometry::PolygonSet& countedRegion(int k) {
        if (!counted[k]) counted[k] = regions[k].offset(band);
        return *counted[k];
    }
};

ExposureErrorSink::ExposureErrorSink(const exposure::ExposureGrid& grid,
                                     std::vector<geometry::PolygonSet> regions, double targetDose,
                                     double band, double surfaceScale, bool keepTopMap)
    : mState(std::make_unique<State>()) {
    if (!(targetDose > 0) || !(band >= 0) || !(surfaceScale > 0))
        throw InputError(
            "exposure error: Etar and the surface scale must be positive and the band "
            "non-negative");
    State& s = *mState;
    s.grid = grid;
    s.regions = std::move(regions);
    s.counted.resize(s.regions.size());
    s.targetDose = targetDose;
    s.band = band;
    s.surfaceScale = surfaceScale;
    s.errors.resize(s.regions.size());
    for (int k = int(s.regions.size()) - 1; k >= 0 && s.topLayer < 0; --k)
        if (!s.regions[k].empty()) s.topLayer = k;
    if (keepTopMap && s.topLayer >= 0) s.topMap = grid.surface();
}

ExposureErrorSink::~ExposureErrorSink() = default;
ExposureErrorSink::ExposureErrorSink(ExposureErrorSink&&) noexcept = default;
ExposureErrorSink& ExposureErrorSink::operator=(ExposureErrorSink&&) noexcept = default;

void ExposureErrorSink::add(const exposure::ExposureSlice& slice) {
    State& s = *mState;
    const int k = slice.layer;
    if (slice.slice != 0 || k < 0 || k >= int(s.regions.size()) || s.regions[k].empty()) return;
    const exposure::SurfaceGrid& values = *slice.values;
    const exposure::CellWindow w = slice.owned();
    if (w.i0 < values.firstI || w.j0 < values.firstJ || w.i1 > values.firstI + values.nx ||
        w.j1 > values.firstJ + values.ny || w.i1 > s.grid.nx || w.j1 > s.grid.ny)
        throw ResourceError("exposure slice does not match the exposure-error grid");
    exposure::SurfaceGrid cells;  // the owned window's cells (no values), for the masks
    cells.nx = w.width();
    cells.ny = w.height();
    cells.originX = s.grid.originX;
    cells.originY = s.grid.originY;
    cells.pitch = s.grid.pitch;
    cells.firstI = w.i0;
    cells.firstJ = w.j0;
    std::vector<geometry::Contour> contours = s.regions[k].contours();
    if (w.i0 != s.maskWindow.i0 || w.j0 != s.maskWindow.j0 || w.i1 != s.maskWindow.i1 ||
        w.j1 != s.maskWindow.j1 || contours != s.maskContours) {
        s.inside = insideMask(s.regions[k], cells);
        s.countedCells = insideMask(s.countedRegion(k), cells);
        s.maskContours = std::move(contours);
        s.maskWindow = w;
    }
    const ExposureError tile = detail::windowError(values, w, s.inside, s.countedCells,
                                                   s.targetDose, s.surfaceScale, &s.histogram);
    detail::addSums(s.errors[k], tile);
    if (k != s.topLayer || s.topMap.values.empty()) return;
    for (int j = w.j0; j < w.j1; ++j)
        for (int i = w.i0; i < w.i1; ++i)
            s.topMap.at(i, j) =
                float(values.at(i - values.firstI, j - values.firstJ) * s.surfaceScale);
}

nlohmann::json ExposureErrorSink::result(ExposureError* all) {
    State& s = *mState;
    std::vector<ExposureError> errors = s.errors;  // the sums stay open for more tiles
    return detail::exposureErrorJson(errors, s.regions, s.targetDose, s.band, s.histogram, all);
}

void ExposureErrorSink::savePicture(BinaryStateWriter& out) const {
    out.add("exposure_error.top_map", mState->topMap.values);
}

void ExposureErrorSink::restorePicture(const BinaryStateReader& in) {
    std::vector<float>& map = mState->topMap.values;
    map = in.take<float>("exposure_error.top_map", map.size());
}

void ExposureErrorSink::savePartialPicture(BinaryStateWriter& out,
                                           const exposure::CellWindow& core) const {
    const exposure::SurfaceGrid& map = mState->topMap;
    std::vector<float> window;
    if (!map.values.empty())
        for (int j = core.j0; j < core.j1; ++j)
            window.insert(window.end(),
                          map.values.begin() + ptrdiff_t(size_t(j) * map.nx + core.i0),
                          map.values.begin() + ptrdiff_t(size_t(j) * map.nx + core.i1));
    out.add("exposure_error.tile_top_map", window);
}

void ExposureErrorSink::mergePicture(const BinaryStateReader& in,
                                     const exposure::CellWindow& core) {
    exposure::SurfaceGrid& map = mState->topMap;
    const size_t cells = map.values.empty() ? 0 : size_t(core.width()) * size_t(core.height());
    const std::vector<float> window = in.take<float>("exposure_error.tile_top_map", cells);
    for (int j = core.j0; j < core.j1 && cells; ++j)
        std::copy_n(&window[size_t(j - core.j0) * core.width()], core.width(), &map.at(core.i0, j));
}

const exposure::SurfaceGrid& ExposureErrorSink::topMap() const {
    return mState->topMap;
}

nlohmann::json ExposureErrorSink::saveState() {
    State& s = *mState;
    nlohmann::json layers = nlohmann::json::array();
    for (int k = 0; k < int(s.errors.size()); ++k) {
        const ExposureError& e = s.errors[k];
        if (e.cells > 0) layers.push_back({k, e.sse, e.cells, e.maxRelative});
    }
    return {{"layers", layers}, {"histogram", s.histogram.state()}};
}

void ExposureErrorSink::restoreState(const nlohmann::json& state) {
    State& s = *mState;
    std::fill(s.errors.begin(), s.errors.end(), ExposureError{});
    s.histogram.clear();
    mergeState(state);
}

void ExposureErrorSink::mergeState(const nlohmann::json& later) {
    State& s = *mState;
    try {
        for (const auto& l : later.at("layers")) {
            const int k = l.at(0).get<int>();
            if (k < 0 || k >= int(s.errors.size()))
                throw InputError("malformed exposure-error state: layer " + std::to_string(k) +
                                 " out of range");
            detail::addSums(
                s.errors[k],
                {l.at(1).get<double>(), 0.0, l.at(3).get<double>(), l.at(2).get<int>(), {}});
        }
        s.histogram.addState(later.at("histogram"));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed exposure-error state: ") + e.what());
    }
}

}  // namespace vpsim::optimise
