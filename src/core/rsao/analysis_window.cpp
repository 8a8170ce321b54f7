#include "room_reverb/rsao/analysis_window.h"

#include <algorithm>
#include <cmath>

namespace room_reverb::core {

SampleWindow hammingWindowAt(double centre_sample, double length_samples, std::size_t signal_length) {
  constexpr double kPi = 3.14159265358979323846;
  SampleWindow window;
  const double half = 0.5 * length_samples;
  const double lo = std::max(0.0, std::ceil(centre_sample - half));
  const double hi = std::min(static_cast<double>(signal_length) - 1.0, std::floor(centre_sample + half));
  if (!(length_samples > 0.0) || hi < lo) return window;
  window.first = static_cast<std::size_t>(lo);
  const auto count = static_cast<std::size_t>(hi - lo) + 1;
  window.weights.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double t = lo + static_cast<double>(i) - centre_sample;
    window.weights[i] = 0.54 + 0.46 * std::cos(2.0 * kPi * t / length_samples);
  }
  return window;
}

}  // namespace room_reverb::core
