#pragma once
/// @file
/// Lets C++ compile the physics written once in shaders/include/*.glsl (docs/ARCHITECTURE.md: one
/// physics source for CPU and GPU). GLM mirrors GLSL's types and functions; the few spellings that
/// differ are macros that shaders/include/glsl_common.glsl defines for GLSL.
///
/// Use it like this in a .cpp (the library adds shaders/include to the include path):
///   #include "vpsim/core/glsl_shim.h"
///   namespace vpsim::glsl {
///   #include "shared_structs.glsl"      // structs: plain namespace (identical in every TU)
///   namespace {                          // functions: unnamed namespace, since GLSL functions
///   #include "rng.glsl"                  // cannot be declared inline and several .cpp files
///   }                                    // may include the same file
///   }
///
/// Rules for shared .glsl files: include guards (no #pragma once); parameters passed by reference
/// use VPSIM_INOUT(T) / VPSIM_OUT(T); no GLSL-only built-ins outside `#ifndef VPSIM_CPU` blocks;
/// literals typed explicitly (1.0f is not GLSL 450: write float(1) or 1.0 and keep C++ float
/// arithmetic by casting); structs shared with C++ use only 4-byte scalars and vec4/uvec4/ivec4
/// members so std430 and C++ layouts agree (checked by tests/gpu/test_struct_layout.cpp).

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>

#define VPSIM_CPU 1
// A translation unit uses only some functions of an included .glsl file.
#pragma GCC diagnostic ignored "-Wunused-function"
#define VPSIM_INOUT(T) T&
#define VPSIM_OUT(T) T&

namespace vpsim::glsl {
using namespace glm;
using uint = glm::uint;
}  // namespace vpsim::glsl
