#pragma once
/// @file
/// Signed distance of the cured surface from the reference model, sampled at the cured mesh's
/// vertices in the reference level set: positive where the cured part sticks out of the model
/// (over-cure), negative where it falls short.

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/geometry/level_set.h"
#include "vpsim/geometry/mesh.h"

namespace vpsim::validate {

struct SurfaceDeviation {
    double mean = 0;  ///< signed mean (mm)
    double rms = 0;   ///< root mean square (mm)
    double p95 = 0;   ///< 95th percentile of |deviation| (mm)
    double max = 0;   ///< largest |deviation| (mm)
    size_t samples = 0;
    /// Samples beyond the level set's band, where the distance is only known to exceed it.
    size_t beyondBand = 0;
    nlohmann::json toJson() const;
};

/// Running statistics of signed deviations clamped to +-band (mm), so a run need not keep one
/// value per cured vertex: count, sum and sum of squares (in the order added; parts merge in a
/// fixed order), the extremes, and a histogram of the signed deviation in 2 BINS equal bins over
/// [-band, band] for percentiles of |deviation| and the report's histogram (to band / BINS: 4 nm
/// for the 0.25 mm band).
class DeviationStatistics {
public:
    static constexpr int BINS = 1 << 16;
    explicit DeviationStatistics(double band = 1.0);
    void add(float deviation);
    /// Appends `later` (same band): the result of adding this one's samples, then its own.
    void merge(const DeviationStatistics& later);
    uint64_t count() const { return mCount; }
    double band() const { return mBand; }
    /// The |deviation| of 0-based rank `k` in ascending order, to a bin: the bin's upper edge.
    double magnitudeAtRank(uint64_t k) const;
    /// Samples with |deviation| > `limit`, to a bin (a bin counts when its middle is above).
    uint64_t countAbove(double limit) const;
    /// The smallest and the largest signed deviation (0 when there are none).
    double minimum() const { return mMin; }
    double maximum() const { return mMax; }
    /// Counts in `bins` equal bins over [lo, hi] (lo < hi), to a bin of the histogram (each of
    /// its bins counts where its middle falls); samples outside go to the end bins.
    std::vector<uint64_t> histogram(double lo, double hi, int bins) const;
    /// mean, rms, max and beyond_band as summarizeDeviations gives them; p95 to a bin.
    /// @throw InputError when there are none (nothing cured)
    SurfaceDeviation summary() const;
    /// The exact state (JSON numbers keep doubles to the bit), for checkpoints and MPI;
    /// fromJson checks its shape. @throw InputError for a malformed state
    nlohmann::json toJson() const;
    static DeviationStatistics fromJson(const nlohmann::json& state);

private:
    double mBand;
    uint64_t mCount = 0, mBeyondBand = 0;
    double mSum = 0, mSumSq = 0, mMaxAbs = 0, mMin = 0, mMax = 0;
    std::vector<uint64_t> mHistogram;  ///< 2 BINS: bin BINS + k holds [k, k + 1) band / BINS
    /// The magnitude bin k's count: both signs.
    uint64_t magnitudeCount(size_t k) const {
        return mHistogram[BINS + k] + mHistogram[BINS - 1 - k];
    }
};

/// @throw InputError when the cured mesh is empty (nothing cured)
SurfaceDeviation measureSurfaceDeviation(const geometry::Mesh& cured,
                                         const geometry::LevelSet& reference);

/// Statistics of signed deviations (mm) sampled in a level set of band half-width `bandHalfWidth`.
/// @throw InputError when there are none (nothing cured)
SurfaceDeviation summarizeDeviations(const std::vector<float>& deviations, double bandHalfWidth);

/// Signed deviations (mm) at each cured vertex, for histograms and deviation maps.
std::vector<float> vertexDeviations(const geometry::Mesh& cured,
                                    const geometry::LevelSet& reference);

}  // namespace vpsim::validate
