#pragma once
// Private: strided row copies between host grids and the shaders' padded buffers (their host
// mirrors), one TBB task per block of rows.
#include <cstddef>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vpsim::exposure {

/// Copies `rows` rows of `width` floats from `from` (rows `fromStride` floats apart) to `to`
/// (rows `toStride` floats apart).
inline void copyRows(float* to, size_t toStride, const float* from, size_t fromStride, size_t width,
                     size_t rows) {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, rows, 16), [&](const tbb::blocked_range<size_t>& range) {
            for (size_t j = range.begin(); j < range.end(); ++j)
                std::memcpy(to + j * toStride, from + j * fromStride, width * sizeof(float));
        });
}

}  // namespace vpsim::exposure
