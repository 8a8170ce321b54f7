#pragma once
// A synthetic HRTF set with known interaural cues, for the binaural tests: the spherical
// head model of Brown & Duda ("A structural model for binaural sound synthesis", IEEE
// Trans. Speech Audio Process. 6(5), 1998): per ear a first-order head-shadow filter and
// a Woodworth-Schlosberg delay, both functions of the angle between the source and that
// ear's axis. Ears at azimuth +-90 deg, head radius 8.75 cm, no pinna and no torso, so
// the set is exactly left/right and front/back symmetric.
#include <Eigen/Core>
#include <cstddef>

#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/hrtf_set.h"

namespace room_reverb::test {

constexpr double kHeadRadiusM = 0.0875;
constexpr double kHeadSpeedOfSoundMS = 343.0;
constexpr std::size_t kSphericalHeadHrirLength = 128;

// The model's HRIR pair for a direction (head frame), 128 taps at 48 kHz. Both ears are
// delayed by a common 16 samples plus head radius / c, so every onset is causal.
core::Hrir sphericalHeadHrir(const Eigen::Vector3d& direction);

// The model's ITD (right-ear delay minus left-ear delay, seconds): Woodworth's
// (a / c)(theta + sin theta) for a source at lateral angle theta.
double sphericalHeadItdS(const Eigen::Vector3d& direction);

// The model rendered on `direction_count` near-uniform (Fibonacci) directions at 48 kHz.
core::HrtfSet sphericalHeadHrtfSet(std::size_t direction_count = 1000);

// The default (MagLS) decoder of that set at `order`, made once per order and kept.
const core::BinauralDecoder& sphericalHeadDecoder(int order);

}  // namespace room_reverb::test
