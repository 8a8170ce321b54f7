#pragma once
// ROOM_REVERB_SIMD_CLONES before a function built for baseline x86-64 (SSE2) adds an
// AVX2/FMA copy of it, chosen when the library loads (GCC's target_clones), so a hot loop
// runs at twice the vector width where the CPU has it while the library still runs on any
// x86-64. Only for plain functions with external linkage (the dispatch is an ifunc).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define ROOM_REVERB_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define ROOM_REVERB_SIMD_CLONES
#endif
