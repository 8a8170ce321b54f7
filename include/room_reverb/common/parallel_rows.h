#pragma once
// Image rows shared among worker threads. Each row is computed by one call that depends
// on nothing but its row index, so the image is the same for any thread count.
#include <functional>

namespace room_reverb::core {

// Calls body(row) once for every row in [0, rows), on `threads` threads (0: the
// hardware's count). An exception from a body is rethrown after all threads stop.
void forEachRow(int rows, int threads, const std::function<void(int)>& body);

}  // namespace room_reverb::core
