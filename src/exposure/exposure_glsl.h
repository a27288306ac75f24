#pragma once
// The exposure arithmetic of shaders/include/exposure.glsl, compiled as C++ (glsl_shim.h).
#include "vpsim/core/glsl_shim.h"

namespace vpsim::glsl {
#include "shared_structs.glsl"
namespace {  // GLSL functions are not inline: one private copy per translation unit
#include "exposure.glsl"
}  // namespace
}  // namespace vpsim::glsl
