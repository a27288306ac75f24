#pragma once
// Inner loops of cure_field.cpp. conversion_kernel.cpp is compiled with -ffast-math (see
// CMakeLists.txt) so GCC vectorises expf through glibc's libmvec; the mask loop needs no such flag.

#include <cstddef>
#include <cstdint>

namespace vpsim::cure::detail {

/// out[i] = 1 - exp(-min(k max(dose[i], 0), 80)), float. Absolute error ~1e-7; NaN doses give an
/// unspecified value (fast-math assumes finite inputs).
void fppConversionRange(const float* dose, size_t count, float k, float* out);

}  // namespace vpsim::cure::detail
