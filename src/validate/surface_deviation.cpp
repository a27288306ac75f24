#include "vpsim/validate/surface_deviation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

namespace vpsim::validate {

std::vector<float> vertexDeviations(const geometry::Mesh& cured,
                                    const geometry::LevelSet& reference) {
    std::vector<float> deviations;
    reference.sample(cured.vertices, deviations);
    return deviations;
}

SurfaceDeviation measureSurfaceDeviation(const geometry::Mesh& cured,
                                         const geometry::LevelSet& reference) {
    if (cured.vertices.empty()) throw InputError("nothing cured: the cured surface is empty");
    return summarizeDeviations(vertexDeviations(cured, reference), reference.halfWidth());
}

SurfaceDeviation summarizeDeviations(const std::vector<float>& d, double bandHalfWidth) {
    if (d.empty()) throw InputError("nothing cured: the cured surface is empty");
    SurfaceDeviation out;
    out.samples = d.size();
    const double band = bandHalfWidth * (1.0 - 1e-6);
    double sum = 0, sumSq = 0;
    std::vector<float> magnitude(d.size());
    for (size_t i = 0; i < d.size(); ++i) {
        sum += d[i];
        sumSq += double(d[i]) * d[i];
        magnitude[i] = std::abs(d[i]);
        out.beyondBand += magnitude[i] >= band;
    }
    out.mean = sum / double(d.size());
    out.rms = std::sqrt(sumSq / double(d.size()));
    size_t rank = size_t(std::ceil(0.95 * double(d.size()))) - 1;
    std::nth_element(magnitude.begin(), magnitude.begin() + rank, magnitude.end());
    out.p95 = magnitude[rank];
    out.max = *std::max_element(magnitude.begin(), magnitude.end());
    return out;
}

DeviationStatistics::DeviationStatistics(double band) : mBand(band), mHistogram(2 * BINS, 0) {
    if (!(band > 0)) throw InputError("deviation statistics need a positive band");
}

void DeviationStatistics::add(float deviation) {
    const double magnitude = std::abs(deviation);
    mMin = mCount ? std::min(mMin, double(deviation)) : deviation;
    mMax = mCount ? std::max(mMax, double(deviation)) : deviation;
    ++mCount;
    mSum += deviation;
    mSumSq += double(deviation) * deviation;
    mMaxAbs = std::max(mMaxAbs, magnitude);
    mBeyondBand += magnitude >= mBand * (1.0 - 1e-6);
    const size_t k = size_t(std::min<double>(BINS - 1, magnitude / mBand * BINS));
    ++mHistogram[deviation < 0 ? BINS - 1 - k : BINS + k];
}

void DeviationStatistics::merge(const DeviationStatistics& later) {
    if (later.mBand != mBand) throw InputError("merging deviation statistics of different bands");
    if (later.mCount) {
        mMin = mCount ? std::min(mMin, later.mMin) : later.mMin;
        mMax = mCount ? std::max(mMax, later.mMax) : later.mMax;
    }
    mCount += later.mCount;
    mSum += later.mSum;
    mSumSq += later.mSumSq;
    mMaxAbs = std::max(mMaxAbs, later.mMaxAbs);
    mBeyondBand += later.mBeyondBand;
    for (size_t b = 0; b < mHistogram.size(); ++b) mHistogram[b] += later.mHistogram[b];
}

double DeviationStatistics::magnitudeAtRank(uint64_t k) const {
    uint64_t below = 0;
    for (size_t b = 0; b < BINS; ++b) {
        below += magnitudeCount(b);
        if (below > k) return std::min(mMaxAbs, double(b + 1) * mBand / BINS);
    }
    return mMaxAbs;
}

uint64_t DeviationStatistics::countAbove(double limit) const {
    uint64_t above = 0;
    for (size_t b = 0; b < BINS; ++b)
        if ((double(b) + 0.5) * mBand / BINS > limit) above += magnitudeCount(b);
    return above;
}

std::vector<uint64_t> DeviationStatistics::histogram(double lo, double hi, int bins) const {
    if (!(hi > lo) || bins < 1) throw InputError("a deviation histogram needs lo < hi and bins");
    std::vector<uint64_t> counts(size_t(bins), 0);
    for (size_t b = 0; b < mHistogram.size(); ++b) {
        if (!mHistogram[b]) continue;
        const double middle = (double(b) - BINS + 0.5) * mBand / BINS;
        const double at = std::floor((middle - lo) / (hi - lo) * bins);  // clamped before int
        counts[size_t(std::clamp(at, 0.0, double(bins - 1)))] += mHistogram[b];
    }
    return counts;
}

SurfaceDeviation DeviationStatistics::summary() const {
    if (mCount == 0) throw InputError("nothing cured: the cured surface is empty");
    SurfaceDeviation out;
    out.samples = mCount;
    out.beyondBand = mBeyondBand;
    out.mean = mSum / double(mCount);
    out.rms = std::sqrt(mSumSq / double(mCount));
    out.p95 = magnitudeAtRank(uint64_t(std::ceil(0.95 * double(mCount))) - 1);
    out.max = mMaxAbs;
    return out;
}

nlohmann::json DeviationStatistics::toJson() const {
    nlohmann::json bins = nlohmann::json::array();  // [bin, count] of the filled signed bins
    for (size_t b = 0; b < mHistogram.size(); ++b)
        if (mHistogram[b]) bins.push_back({b, mHistogram[b]});
    return {{"band", mBand}, {"count", mCount},  {"beyond_band", mBeyondBand},
            {"sum", mSum},   {"sum_sq", mSumSq}, {"max_abs", mMaxAbs},
            {"min", mMin},   {"max", mMax},      {"signed_histogram", bins}};
}

DeviationStatistics DeviationStatistics::fromJson(const nlohmann::json& state) {
    try {
        DeviationStatistics s(state.at("band").get<double>());
        s.mCount = state.at("count").get<uint64_t>();
        s.mBeyondBand = state.at("beyond_band").get<uint64_t>();
        s.mSum = state.at("sum").get<double>();
        s.mSumSq = state.at("sum_sq").get<double>();
        s.mMaxAbs = state.at("max_abs").get<double>();
        s.mMin = state.at("min").get<double>();
        s.mMax = state.at("max").get<double>();
        for (const auto& bin : state.at("signed_histogram"))
            s.mHistogram.at(bin.at(0).get<size_t>()) = bin.at(1).get<uint64_t>();
        return s;
    } catch (const nlohmann::json::exception& e) {
        throw InputError(std::string("malformed deviation statistics: ") + e.what());
    } catch (const std::out_of_range&) {
        throw InputError("malformed deviation statistics: a histogram bin out of range");
    }
}

nlohmann::json SurfaceDeviation::toJson() const {
    return {{"mean", mean}, {"rms", rms},         {"p95", p95},
            {"max", max},   {"samples", samples}, {"beyond_band", beyondBand}};
}

}  // namespace vpsim::validate
