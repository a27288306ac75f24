#version 450
// Tabulated-kernel exposure: adds one depth stencil's gather of a layer's deposit to one voxel
// slice (see include/vpsim/exposure/tabulated_engine.h). out(i, j) += sum w(di, dj) S(i+di, j+dj).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "exposure.glsl"

layout(push_constant) uniform Push { ExposureStencilParams params; };
layout(std430, binding = 0) readonly buffer Deposit { float deposit[]; };
layout(std430, binding = 1) readonly buffer Weights { float weights[]; };
layout(std430, binding = 2) buffer Slice { float slice[]; };

void main() {
    uint index = flatInvocationIndex();
    if (index >= params.nx * params.ny) return;
    int nx = int(params.nx), ny = int(params.ny), H = params.halfWidth;
    int i = int(index % params.nx), j = int(index / params.nx);
    float sum = 0.0;
    for (int dj = -H; dj <= H; ++dj) {
        int sj = j + dj;
        if (sj < 0 || sj >= ny) continue;
        for (int di = max(-H, -i); di <= min(H, nx - 1 - i); ++di)
            sum += weights[params.weightOffset + uint(stencilIndex(di, dj, H))] * deposit[sj * nx + i + di];
    }
    slice[index] += sum;
}
