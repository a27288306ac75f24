#pragma once
/// @file
/// What the two ways of computing the laser exposure-error metric share: the standalone one
/// (planExposureError, which exposes each layer on its own grid) and the streamed one
/// (ExposureErrorSink, which reads the run's slices): the |error| / Etar histogram, one window's
/// sums and the report's JSON. Private to the optimise module.

#include <cstdint>
#include <utility>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <nlohmann/json.hpp>

#include "vpsim/exposure/exposure_model.h"
#include "vpsim/optimise/laser/exposure_error.h"

namespace vpsim::optimise::detail {

/// |E - Etm| / Etar of every counted cell of every layer, as a histogram: the sorted curve of
/// Fig. 23 over 1e8 cells would otherwise be a 400 MB sort, and its figure shows 400 points.
/// Bins of 1/16384 Etar up to 4 Etar (the curve's error is under a bin), exact values beyond.
/// Each thread counts apart (gather() adds them): integer counts and a list sorted later, so
/// neither the threads nor the order of tiles and merges change the result.
class ErrorHistogram {
public:
    static constexpr int BINS = 65536;
    static constexpr float SCALE = 16384.0f;                              ///< bins per Etar
    using Counts = std::pair<std::vector<uint64_t>, std::vector<float>>;  ///< bins, beyond

    ErrorHistogram();
    /// This thread's counts, for add().
    Counts& local() { return mLocal.local(); }
    static void add(float relative, Counts& counts) {
        const float bin = relative * SCALE;
        if (bin < float(BINS))
            ++counts.first[int(bin)];
        else
            counts.second.push_back(relative);
    }
    /// Adds every thread's counts to the total and empties them.
    void gather();
    /// The sorted curve at 2001 evenly spaced ranks (first and last exact to a bin).
    std::vector<float> quantiles(uint64_t cells);
    /// The gathered counts (sparse: [bin, count] pairs) and the values beyond.
    nlohmann::json state();
    /// Adds a state() of counts made elsewhere.
    /// @throw nlohmann::json::exception when malformed, InputError for a bin out of range
    void addState(const nlohmann::json& state);
    void clear();

private:
    Counts mTotal;
    tbb::enumerable_thread_specific<Counts> mLocal;
};

/// The metric's sums over `window` (cells of the whole grid) of the exposure `values` (which
/// holds the window; a tile's grid or the whole one) times `scale`, against Etar where `inside`
/// and 0 elsewhere, counting the cells where `counted` (both masks row-major over the window).
/// Rows in parallel, each row's sums kept apart and added in row order, so the result does not
/// depend on the threads. rmsRelative is left to finishLayer().
ExposureError windowError(const exposure::SurfaceGrid& values, const exposure::CellWindow& window,
                          const std::vector<char>& inside, const std::vector<char>& counted,
                          double targetDose, double scale, ErrorHistogram* histogram);

/// `part`'s sums added to `total`'s: SSE and cells add, the maximum is the larger.
void addSums(ExposureError& total, const ExposureError& part);

/// planExposureError's JSON (see there) from the per-layer sums of the layers whose region is
/// not empty; fills each layer's rmsRelative, and `all` (optional) with the total and the
/// sorted curve from `histogram` (gathered here).
nlohmann::json exposureErrorJson(std::vector<ExposureError>& errors,
                                 const std::vector<geometry::PolygonSet>& regions,
                                 double targetDose, double band, ErrorHistogram& histogram,
                                 ExposureError* all);

}  // namespace vpsim::optimise::detail
