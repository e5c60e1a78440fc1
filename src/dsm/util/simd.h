// SPDX-License-Identifier: MIT
// DSM_SIMD_CLONES marks a hot loop's function to be compiled twice: for AVX2 (8 floats a vector,
// a column of the tracker's 8x8 normal equations in one register) and for the x86-64 baseline
// (SSE2, 4 floats); the dynamic loader picks the one the CPU runs (an ifunc), so one binary runs
// on every x86-64 CPU. Only the function's own code is cloned: Eigen inside it keeps the
// baseline's packets and alignment, so the clone shares every type's layout with the rest of the
// program (compiling the whole program for the host, -march=native, changes Eigen's alignment and
// breaks against the system's prebuilt Eigen-based libraries). With ISO C++ floating-point
// contraction is off: the clones compute the same element-wise values; only reductions may add
// in another order (the shared EuRoC frames come out byte-identical either way). Off x86-64, in
// sanitizer builds (their runtime is not up when the loader picks a clone), and with the CMake
// option DSM_SIMD_CLONES=OFF (one baseline build, e.g. to compare against).
#pragma once

// DSM_X86_SIMD is 1 where the clones are made: code with hand-written AVX2 (target("avx2"),
// picked at run time by __builtin_cpu_supports) keeps to the same builds.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(DSM_NO_SIMD_CLONES)
#define DSM_X86_SIMD 1
#define DSM_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define DSM_X86_SIMD 0
#define DSM_SIMD_CLONES
#endif
