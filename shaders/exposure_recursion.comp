#version 450
// Print-through recursion R = B + a R over one layer (see exposure_engine.h).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"

layout(push_constant) uniform Push { ExposureRecursionParams params; };
layout(std430, binding = 0) readonly buffer Blurred { float blurred[]; };
layout(std430, binding = 1) buffer Running { float running[]; };

void main() {
    uint index = flatInvocationIndex();
    if (index >= params.count) return;
    running[index] = printThroughStep(blurred[index], running[index], params.decay);
}
