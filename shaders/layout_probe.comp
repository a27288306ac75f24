#version 450
// Never dispatched: declares one buffer per shared struct so the struct-layout test can read the
// std430 offsets that glslang assigns from this shader's SPIR-V. Add a line for each new struct.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 1) in;

#include "glsl_common.glsl"
#include "shared_structs.glsl"
#include "photon_types.glsl"

layout(std430, binding = 0) buffer ProbeRngStreamParams { RngStreamParams probeRngStreamParams[]; };

layout(std430, binding = 1) buffer ProbeExposureBlurParams { ExposureBlurParams probeExposureBlurParams[]; };
layout(std430, binding = 2) buffer ProbePhotonParams { PhotonParams probePhotonParams[]; };
layout(std430, binding = 3) buffer ProbeExposureStencilParams { ExposureStencilParams probeExposureStencilParams[]; };

void main() {
    probeRngStreamParams[0].seed = 0u;
    probeExposureBlurParams[0].nx = 0u;
    probePhotonParams[0].seed = 0u;
    probeExposureStencilParams[0].nx = 0u;
}
