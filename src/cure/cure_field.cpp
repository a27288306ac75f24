#include "vpsim/cure/cure_field.h"

#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace vpsim::cure {
namespace {

/// Chunks of 1 Mi voxels: large enough that scheduling costs nothing next to the memory traffic.
constexpr size_t GRAIN = size_t(1) << 20;

template <class Body>
void forChunks(size_t count, const Body& body) {
    if (count <= GRAIN) {
        body(size_t(0), count);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, GRAIN),
                      [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
}

/// The loop lives in its own function with plain pointer arguments: inside a lambda capturing by
/// reference, the byte stores could alias the captured pointers and the loop would not vectorise.
void maskRange(const float* dose, size_t count, float level, uint8_t* cured) {
    for (size_t i = 0; i < count; ++i) cured[i] = uint8_t(dose[i] >= level);
}

}  // namespace

void cureMask(const CureLaw& law, const float* dose, size_t count, uint8_t* cured) {
    // Compare in float against the iso-level rounded to float: the branch-free loop vectorises.
    const float level = float(law.criticalDose());
    forChunks(count, [=](size_t begin, size_t end) {
        maskRange(dose + begin, end - begin, level, cured + begin);
    });
}

std::vector<uint8_t> cureMask(const CureLaw& law, const std::vector<float>& dose) {
    std::vector<uint8_t> cured(dose.size());
    cureMask(law, dose.data(), dose.size(), cured.data());
    return cured;
}

void conversionField(const CureLaw& law, const float* dose, size_t count, float* conversion) {
    forChunks(count, [&](size_t begin, size_t end) {
        law.conversionRange(dose + begin, end - begin, conversion + begin);
    });
}

std::vector<float> conversionField(const CureLaw& law, const std::vector<float>& dose) {
    std::vector<float> conversion(dose.size());
    conversionField(law, dose.data(), dose.size(), conversion.data());
    return conversion;
}

size_t countCured(const CureLaw& law, const float* dose, size_t count) {
    const float level = float(law.criticalDose());
    auto countRange = [&](size_t begin, size_t end) {
        size_t n = 0;
        for (size_t i = begin; i < end; ++i) n += size_t(dose[i] >= level);
        return n;
    };
    if (count <= GRAIN) return countRange(0, count);
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, count, GRAIN), size_t(0),
        [&](const tbb::blocked_range<size_t>& r, size_t n) {
            return n + countRange(r.begin(), r.end());
        },
        [](size_t a, size_t b) { return a + b; });
}

}  // namespace vpsim::cure
