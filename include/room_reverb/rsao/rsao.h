#pragma once
// The reverberant spatial audio object (RSAO) of Remaggi et al. / Coleman et al. (S3A):
// a direct sound and early reflections, each a delayed, filtered, directional tap, and a
// late reverb described per octave band by a level, an onset ramp and an exponential decay.
// This header holds the data (and where a reflection's image source lies); estimation,
// resynthesis and file formats live in their own headers of the rsao module.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {

// One second-order section, normalised so that a0 = 1:
// H(z) = (b0 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2).
struct BiquadSection {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0;
  double a1 = 0.0, a2 = 0.0;
};

// The direct sound (index 0 of Rsao::reflections) or one early reflection.
struct EarlyReflection {
  double time_of_arrival_s = 0.0;  // from the first sample of the RIR (48 kHz time base)
  // A_k (linear): the direct sound's, and with the paper's onsets every arrival's, is
  // sqrt(E_k) of the W channel over the analysis window; with matching pursuit a
  // reflection's is its own amplitude in W (early_reflections.h). A renderer scales the
  // filtered tap to it.
  double level = 0.0;
  double azimuth_rad = 0.0;        // DESIGN.md: counter-clockwise from +x, [-pi, pi)
  double elevation_rad = 0.0;      // up from the horizontal plane, [-pi/2, pi/2]
  // Distance of the (image) source [m]: the direct sound's distance (given, or c times its
  // time of arrival when the RIR starts at the emission) plus c times the delay after
  // it. With the direction this places the image source: distance * (cos el cos az,
  // cos el sin az, sin el) in the microphone's frame (imageSourcePosition).
  double distance_m = 0.0;
  // How far the estimate can be trusted, 0..1: the share of the energy that arrives as one
  // plane wave (CardioidSteeringStatistics::directness), of the analysis window with the
  // paper's onsets, of the arrival's own projection with matching pursuit. Low where two
  // arrivals from different directions overlap or the diffuse field dominates. Not set
  // for an RSAO that was read from a file without it.
  std::optional<double> confidence;
  // All-pole spectral shape 1 / A(z) of the reflection, A(z) = 1 + sum_{i>=1} lpc[i] z^-i
  // (lpc[0] == 1), fitted by Levinson-Durbin; lpc_gain is the prediction-error gain.
  std::vector<double> lpc;
  double lpc_gain = 1.0;
  // The same filter as cascaded sections, its gain giving the energy of W under the
  // analysis window.
  std::vector<BiquadSection> sos;
};

// The reflection's (image) source in the microphone's frame [m]: distance_m along its
// direction of arrival (DESIGN.md axes: x forward, y left, z up).
std::array<double, 3> imageSourcePosition(const EarlyReflection& reflection);

// Late reverberation in one octave band.
struct LateReverbBand {
  double center_hz = 0.0;
  double decay_constant_per_s = 0.0;  // energy envelope ~ exp(-2 * decay_constant * t): amplitude ~ exp(-decay_constant * t)
  double t60_s = 0.0;                 // 3 ln(10) / decay_constant
  double level = 0.0;                 // RMS amplitude of the band's W channel at the mixing time (linear)
  // This project's extension of the onset ramp (late_envelope.h, onset_ramp_fit.h): the
  // band's amplitude at onset_s, from which it moves geometrically to `level` at the mixing
  // time, carrying early energy the discrete reflections leave out. 0: the paper's linear
  // ramp from zero.
  double onset_level = 0.0;
  // This project's extension for bent decays (EDT < T20 < T30; metrics/two_slope_decay.h):
  // with second_share > 0 the envelope's energy after the mixing time is
  //   level^2 ((1 - second_share) exp(-2 first_decay t') + second_share exp(-2 second_decay t')),
  // t' = t - mixing time, first_decay > second_decay the two decay constants [1/s] (of the
  // amplitude, as decay_constant_per_s). decay_constant_per_s and t60_s stay the paper's
  // line over the first 20 dB, which players of one slope (VISR) use. 0: one slope.
  double first_decay_constant_per_s = 0.0;
  double second_decay_constant_per_s = 0.0;
  double second_share = 0.0;
  bool reliable = true;
  std::string reason;                 // why not reliable ("" when reliable)
};

struct LateReverb {
  double mixing_time_s = 0.0;  // from the first sample of the RIR
  double onset_s = 0.0;        // where the ramp starts (the first reflection)
  double attack_time_s = 0.0;  // ramp length: mixing_time_s - onset_s
  // Where the bands' extended early course (LateReverbBand::onset_level, late_envelope.h)
  // joins the exponential decay; at or before the mixing time: at the mixing time.
  double course_end_s = 0.0;
  std::vector<LateReverbBand> bands;  // the nine octave bands 63 Hz..16 kHz
};

struct Rsao {
  double sample_rate_hz = 48000.0;
  double duration_s = 0.0;                   // length of the analysed RIR
  std::vector<EarlyReflection> reflections;  // [0] is the direct sound, then by time of arrival
  LateReverb late;
  std::vector<std::string> warnings;         // problems found that did not stop the estimate
};

}  // namespace room_reverb::core
