// GLSL side of the C++/GLSL common subset (see include/vpsim/core/glsl_shim.h).
#ifndef VPSIM_GLSL_COMMON
#define VPSIM_GLSL_COMMON
#ifndef VPSIM_CPU
#define VPSIM_INOUT(T) inout T
#define VPSIM_OUT(T) out T

/// Flat invocation index of a dispatch made by gpu::Recorder::dispatch1D (folded into Y when the
/// group count exceeds the X limit).
uint flatInvocationIndex() {
    return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}
#endif
#endif
