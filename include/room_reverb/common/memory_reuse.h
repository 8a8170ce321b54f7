#pragma once
// Simulations allocate and free the same large buffers (responses, histograms, band
// spectra) over and over: a diagnosis runs dozens of them. glibc hands freed blocks above
// its thresholds back to the kernel and faults them in again, zeroed, on the next
// allocation; in a diagnosis that is about a tenth of the run time (test_diagnosis_planted's
// scattering case: 19.3-20.0 s as it is, 17.3-17.8 s with freed memory kept). The visual
// route does the same with its clouds, voxel tables and images: on a 2-core virtual
// machine whose page faults are dear, bench_visual_route's point cloud -> room model
// takes 0.65-0.85 s (the paper's kitchen) and 1.03-1.34 s (the courtyard) as it is, and
// 0.38-0.55 s and 0.59-1.01 s with freed memory kept (runs of one session). Processes that run many simulations or
// routes (the command-line tool, the evaluation, room_model and spherical_depth nodes,
// the diagnosis tests, bench_visual_route) call this once at start: freed memory then
// stays with the process for reuse, up to about what the largest job needed.
#include <malloc.h>

namespace room_reverb::core {

inline void keepFreedMemoryForReuse() {
  mallopt(M_MMAP_THRESHOLD, 256 * 1024 * 1024);  // blocks below this come from the heap
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);  // and the heap is trimmed only beyond this
}

}  // namespace room_reverb::core
