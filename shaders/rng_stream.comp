#version 450
// Writes `valuesPerStream` outputs of each RNG stream: used to prove CPU/GPU bit identity.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "rng.glsl"

layout(push_constant) uniform Push { RngStreamParams params; };
layout(std430, binding = 0) writeonly buffer Output { uint words[]; };

void main() {
    uint stream = flatInvocationIndex();
    if (stream >= params.streamCount) return;
    RngState r = rngSeed(params.seed, params.firstStream + stream);
    uint base = stream * params.valuesPerStream;
    for (uint i = 0u; i < params.valuesPerStream; ++i)
        words[base + i] = params.mode == 0u ? rngNext(r) : floatBitsToUint(rngUniform(r));
}
