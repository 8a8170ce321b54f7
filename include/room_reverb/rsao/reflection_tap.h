#pragma once
// One RSAO tap (the direct sound or an early reflection) as a mono signal, before it is
// given a direction: the part every renderer of the object shares (resynthesizeRsao encodes
// it into ambisonics, renderRsaoBinaural convolves it with an HRIR pair).
//
// The tap sits at its exact, fractional time of arrival (a Blackman-windowed sinc), is
// shaped by the reflection's filter (the second-order sections when there are any, else the
// all-pole LPC filter, else none) and kept reflection_response_s long, and carries the gain
// that makes its energy under the estimator's window (a Hamming window of length
// analysis_window_s centred on the arrival, analysis_window.h) EarlyReflection::level^2, so
// that estimating the tap again gives back its level (Remaggi et al. section 2.1: A_k =
// sqrt(E_k) over that window).
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

struct ReflectionTap {
  long first_sample = 0;        // output index of samples[0] (may be negative: cut there)
  std::vector<double> samples;  // the shaped tap, unscaled
  double gain = 0.0;            // the level-matching scale; 0: nothing to place
};

// Tap of reflection `index` (0: the direct sound, for messages) at 48 kHz. A level of 0, or
// a filter that is zero over the window, gives gain 0 and no samples. Throws InputError,
// its message starting with `context`, for an unstable filter.
ReflectionTap shapeReflectionTap(const EarlyReflection& reflection, std::size_t index, double analysis_window_s,
                                 double reflection_response_s, const std::string& context);

// The unit vector the reflection arrives from, in the frame of its azimuth and elevation
// (the rig's, for an estimated RSAO; DESIGN.md direction conventions).
Eigen::Vector3d reflectionDirection(const EarlyReflection& reflection);

// "the direct sound" for index 0, else "reflection <index>".
std::string reflectionName(std::size_t index);

}  // namespace room_reverb::core
