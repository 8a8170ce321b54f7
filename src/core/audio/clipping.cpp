#include "room_reverb/audio/clipping.h"

#include <algorithm>
#include <cmath>

namespace room_reverb::core {

std::size_t findClippedRun(const std::vector<float>& x, std::size_t from, int run) {
  float peak = 0.0f;
  for (float v : x) peak = std::max(peak, std::abs(v));
  if (peak <= 0.0f || run < 2) return x.size();
  const float level = peak * (1.0f - 1e-6f);
  int length = 0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    length = std::abs(x[n]) >= level ? length + 1 : 0;
    const std::size_t start = n + 1 - static_cast<std::size_t>(std::max(length, 1));
    if (length >= run && start >= from) return start;
  }
  return x.size();
}

}  // namespace room_reverb::core
