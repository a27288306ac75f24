// Compiled with -ffast-math (src/cure/CMakeLists.txt): only this loop, so the flag cannot change
// any other arithmetic. target_clones adds an AVX2 version chosen at load time, which calls
// libmvec's 8-wide expf; the default version uses the SSE 4-wide one.
#include "conversion_kernel.h"

#include <cmath>

namespace vpsim::cure::detail {

__attribute__((target_clones("avx2", "default"))) void fppConversionRange(const float* dose,
                                                                          size_t count, float k,
                                                                          float* out) {
    for (size_t i = 0; i < count; ++i) {
        // Clamp the exponent: glibc's vectorised expf drops to a slow scalar path when a lane
        // underflows (docs/PLATFORM.md); exp(-80) = 1.8e-35 is still a normal float and 1 - it
        // is 1.
        float exponent = std::fmin(k * std::fmax(dose[i], 0.0f), 80.0f);
        out[i] = 1.0f - std::exp(-exponent);
    }
}

}  // namespace vpsim::cure::detail
