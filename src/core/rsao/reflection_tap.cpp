#include "room_reverb/rsao/reflection_tap.h"

#include <cmath>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/common/directions.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/analysis_window.h"
#include "room_reverb/rsao/lpc.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFs = kInternalSampleRateHz;
constexpr int kKernelHalfLength = 16;  // fractional-delay taps either side of the arrival

// A section's poles lie inside the unit circle iff (a1, a2) is inside the stability
// triangle |a2| < 1, |a1| < 1 + a2.
bool sectionsStable(const std::vector<BiquadSection>& sections) {
  for (const BiquadSection& s : sections) {
    if (!(std::abs(s.a2) < 1.0 && std::abs(s.a1) < 1.0 + s.a2)) return false;
  }
  return true;
}

// Blackman-windowed sinc interpolating a unit pulse at `fraction` (in [0, 1)) of a sample
// past sample 0; tap i is for sample offset i - kKernelHalfLength + 1.
std::vector<double> fractionalDelayKernel(double fraction) {
  std::vector<double> kernel(2 * kKernelHalfLength);
  for (std::size_t i = 0; i < kernel.size(); ++i) {
    const double x = static_cast<double>(i) - (kKernelHalfLength - 1) - fraction;  // in (-H, H]
    const double sinc = std::abs(x) < 1e-12 ? 1.0 : std::sin(kPi * x) / (kPi * x);
    const double u = x / kKernelHalfLength;
    const double window = 0.42 + 0.5 * std::cos(kPi * u) + 0.08 * std::cos(2.0 * kPi * u);
    kernel[i] = sinc * window;
  }
  return kernel;
}

}  // namespace

std::string reflectionName(std::size_t index) {
  return index == 0 ? std::string("the direct sound") : "reflection " + std::to_string(index);
}

Eigen::Vector3d reflectionDirection(const EarlyReflection& r) {
  return unitVectorFromAngles(r.azimuth_rad, r.elevation_rad);
}

ReflectionTap shapeReflectionTap(const EarlyReflection& r, std::size_t index, double analysis_window_s,
                                 double reflection_response_s, const std::string& context) {
  ReflectionTap out;
  if (r.level == 0.0) return out;
  const double position = r.time_of_arrival_s * kFs;
  const double whole = std::floor(position);
  std::vector<double> tap = fractionalDelayKernel(position - whole);
  tap.resize(tap.size() + static_cast<std::size_t>(std::lround(reflection_response_s * kFs)), 0.0);
  if (!r.sos.empty()) {
    if (!sectionsStable(r.sos)) throw InputError(context + ": " + reflectionName(index) + " has an unstable second-order section");
    tap = filterSections(r.sos, tap);
  } else if (r.lpc.size() > 1) {
    tap = filterAllPole(r.lpc, r.lpc_gain, tap);
    const std::size_t eighth = tap.size() / 8;
    double head = 0.0, tail = 0.0;
    for (std::size_t i = 0; i < eighth; ++i) {
      head += tap[i] * tap[i];
      tail += tap[tap.size() - 1 - i] * tap[tap.size() - 1 - i];
    }
    if (!std::isfinite(tail) || tail > head) {
      throw InputError(context + ": " + reflectionName(index) + "'s LPC filter is unstable (its response grows)");
    }
  }
  // Scale: the energy under the estimator's own window (a Hamming window of length D
  // centred on the arrival, analysis_window.h) is level^2.
  const double centre = static_cast<double>(kKernelHalfLength - 1) + (position - whole);
  const SampleWindow window = hammingWindowAt(centre, analysis_window_s * kFs, tap.size());
  double energy = 0.0;
  for (std::size_t i = 0; i < window.weights.size(); ++i) {
    const double v = window.weights[i] * tap[window.first + i];
    energy += v * v;
  }
  if (!(energy > 0.0)) return out;  // a filter that is zero over the window: nothing to place
  out.gain = r.level / std::sqrt(energy);
  out.first_sample = static_cast<long>(whole) - (kKernelHalfLength - 1);
  out.samples = std::move(tap);
  return out;
}

}  // namespace room_reverb::core
