#pragma once
// SB_SIMD_CLONES: x86-64 builds of a function for AVX2 and for the baseline, picked at load time by the CPU
// (GCC function multiversioning). The lanes make the same IEEE operations either way (no FMA contraction:
// -ffp-contract=off), so results do not depend on the clone; elsewhere (armhf) one build.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SB_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SB_SIMD_CLONES
#endif
