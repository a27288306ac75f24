#pragma once
/// @file
/// Memory budget for allocations sized by user input (a pixel pitch, a voxel, a photon count):
/// checked in bytes before allocating, refused with a ResourceError that says how much, of what,
/// and how to make it fit. The budget comes from the caller's RunContext (the CLI sets it from
/// VPSIM_MEMORY_LIMIT); the library reads no environment.

#include <cstdint>
#include <string>
#include <string_view>

#include "vpsim/core/run_context.h"

namespace vpsim {

/// Half of the physical memory, between 256 MiB and 16 GiB: the budget when none is set.
uint64_t defaultMemoryBudget();

/// Bytes one run may allocate for its largest structures: context.memoryLimit when set (not 0),
/// else defaultMemoryBudget().
uint64_t memoryBudget(const RunContext& context);

/// Where the budget of `context` comes from, for messages: "half the memory, at most 16 GiB;
/// VPSIM_MEMORY_LIMIT sets it" or "set by VPSIM_MEMORY_LIMIT".
std::string memoryBudgetOrigin(const RunContext& context);

/// A memory size as VPSIM_MEMORY_LIMIT writes it: a positive decimal number of bytes, optionally
/// followed by one suffix K, M or G (powers of 1024, either case), nothing else: "5G", "512M",
/// "1.5g", "1073741824".
/// @param name what the text is, for the message (e.g. "VPSIM_MEMORY_LIMIT")
/// @throw InputError naming `name` when the text is anything else (trailing text, spaces, a
///        negative or zero size, a size below one byte or beyond 2^63 bytes)
uint64_t parseMemorySize(std::string_view text, const std::string& name);

/// @param context whose budget applies (memoryBudget(context))
/// @param bytes   estimated size of what is about to be allocated
/// @param what    e.g. "raster pictures of 5200 x 5200 pixels"
/// @param hint    how to make it fit, e.g. "use a coarser --pitch"
/// @throw ResourceError when bytes exceed the budget (or are not finite)
void checkMemory(const RunContext& context, double bytes, const std::string& what,
                 const std::string& hint);

}  // namespace vpsim
