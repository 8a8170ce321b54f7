#pragma once
// ROOM_REVERB_SIMD_CLONES before a function built for baseline x86-64 (SSE2) adds an
// AVX2/FMA copy and an AVX-512 copy of it, chosen when the library loads (GCC's
// target_clones), so a hot loop runs at twice the vector width where the CPU has it while
// the library still runs on any x86-64. The AVX-512 copy keeps 256-bit vectors (GCC's
// default width for it) and gains from its 32 registers and masked tails: a walking
// stream 3-4 % less CPU, the reflection taps 8 % (bench_binaural_renderer, a Xeon with
// AVX-512). Only for plain functions with external linkage (the dispatch is an ifunc).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define ROOM_REVERB_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define ROOM_REVERB_SIMD_CLONES
#endif
