#version 450
// One separable Gaussian pass of the exposure engine (see include/vpsim/exposure/exposure_engine.h).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"

layout(push_constant) uniform Push { ExposureBlurParams params; };
layout(std430, binding = 0) readonly buffer Source { float source[]; };
layout(std430, binding = 1) writeonly buffer Target { float target[]; };

void main() {
    uint index = flatInvocationIndex();
    if (index >= params.nx * params.ny) return;
    int i = int(index % params.nx), j = int(index / params.nx);
    int n = params.axis == 0u ? int(params.nx) : int(params.ny);
    int centre = params.axis == 0u ? i : j;
    int stride = params.axis == 0u ? 1 : int(params.nx);
    int lo = max(-params.halfWidth, -centre), hi = min(params.halfWidth, n - 1 - centre);
    float sum = 0.0;
    for (int o = lo; o <= hi; ++o) sum += gaussianTap(o, params.sigmaCells) * source[int(index) + o * stride];
    target[index] = sum / params.norm;
}
