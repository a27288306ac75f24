#pragma once
/// @file
/// Memory budget for allocations sized by user input (a pixel pitch, a voxel, a photon count):
/// checked in bytes before allocating, refused with a ResourceError that says how much, of what,
/// and how to make it fit.

#include <cstdint>
#include <string>

namespace vpsim {

/// Bytes one command may allocate for its largest structures: VPSIM_MEMORY_LIMIT (bytes, or with
/// a suffix K, M, G) when set, else half of the physical memory, between 256 MiB and 16 GiB.
uint64_t memoryBudget();

/// @param bytes estimated size of what is about to be allocated
/// @param what  e.g. "raster pictures of 5200 x 5200 pixels"
/// @param hint  how to make it fit, e.g. "use a coarser --pitch"
/// @throw ResourceError when bytes exceed memoryBudget() (or are not finite)
void checkMemory(double bytes, const std::string& what, const std::string& hint);

}  // namespace vpsim
