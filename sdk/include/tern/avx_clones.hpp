// sdk/include/tern/avx_clones.hpp: TERN_AVX_CLONES, for a hot loop over doubles that the compiler
// vectorises: on x86-64 with GCC the function is built twice, for AVX (4 doubles a register)
// and for the baseline (SSE2, 2), and the dynamic loader picks the AVX one where the CPU has it
// (GCC's target_clones, resolved by an ifunc). The results are identical either way: the same
// multiplications and additions in the same order per element, and no FMA (that would round
// differently). Elsewhere (another compiler or architecture) it is nothing.
// Not under ThreadSanitizer: the ifunc resolver runs while the object is relocated, before TSan's
// runtime can take its instrumented calls (a plugin's dlopen crashed in it).
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#define TERN_AVX_CLONES __attribute__((target_clones("avx", "default")))
#else
#define TERN_AVX_CLONES
#endif
