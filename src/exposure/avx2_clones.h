#pragma once
/// @file
/// VPSIM_AVX2_CLONES: builds a function for AVX2 as well as the baseline, chosen at run time
/// (GCC/Clang target_clones, x86-64 only; elsewhere nothing). AVX2 alone brings no FMA, so a
/// loop of multiplies and adds gives the same sums bit for bit in either build.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define VPSIM_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define VPSIM_AVX2_CLONES
#endif
