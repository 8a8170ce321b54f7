#pragma once
// Simulations allocate and free the same large buffers (responses, histograms, band
// spectra) over and over: a diagnosis runs dozens of them. glibc hands freed blocks above
// its thresholds back to the kernel and faults them in again, zeroed, on the next
// allocation; in a diagnosis that is about a tenth of the run time (test_diagnosis_planted's
// scattering case: 19.3-20.0 s as it is, 17.3-17.8 s with freed memory kept). Processes
// that run many simulations (the command-line tool, the evaluation node, the diagnosis
// tests) call this once at start: freed memory then stays with the process for reuse,
// up to about what the largest simulation needed.
#include <malloc.h>

namespace room_reverb::core {

inline void keepFreedMemoryForReuse() {
  mallopt(M_MMAP_THRESHOLD, 256 * 1024 * 1024);  // blocks below this come from the heap
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);  // and the heap is trimmed only beyond this
}

}  // namespace room_reverb::core
