#pragma once
/// @file
/// Applies a cure law to whole dose arrays (exposure grids): cured masks and conversion fields.
/// Large arrays are split over threads (TBB); the work is memory-bound (one float read, one byte
/// or float written per voxel), see benchmarks/bench_cure.cpp.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vpsim/cure/cure_law.h"

namespace vpsim::cure {

/// cured[i] = 1 where dose[i] >= law.criticalDose(), else 0. NaN doses count as not cured.
/// @param dose local doses, mJ/mm^2 @param count voxels @param cured output, `count` bytes
void cureMask(const CureLaw& law, const float* dose, size_t count, uint8_t* cured);
/// Convenience overload returning the mask.
std::vector<uint8_t> cureMask(const CureLaw& law, const std::vector<float>& dose);

/// conversion[i] = law.conversion(dose[i]) (dimensionless, FPP: 1 - exp(-K E) in float, absolute
/// error ~1e-7; threshold: 0/1). Negative doses count as 0; a NaN dose gives an unspecified value.
void conversionField(const CureLaw& law, const float* dose, size_t count, float* conversion);
std::vector<float> conversionField(const CureLaw& law, const std::vector<float>& dose);

/// Number of cured voxels (dose >= criticalDose) without building a mask.
size_t countCured(const CureLaw& law, const float* dose, size_t count);

}  // namespace vpsim::cure
