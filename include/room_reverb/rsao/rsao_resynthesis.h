#pragma once
// Resynthesis of a first-order ambisonic RIR from an RSAO (Remaggi et al.; Coleman et al.,
// S3A object-based reverb): the parametric room played back, for listening, for rendering
// with the binaural renderer, and to check the estimator against its own output.
//
// Output: AmbiX first order (four channels, ACN W, Y, Z, X, SN3D) at 48 kHz.
//
// Direct sound and early reflections: each a tap at its exact, fractional time of arrival
// (a windowed-sinc fractional delay), shaped by its filter (the second-order sections when
// there are any, else the all-pole LPC filter, else none), scaled so that the W energy of
// the shaped tap under a Hamming window of length analysis_window_s centred on its arrival
// (the estimator's window) is EarlyReflection::level^2, and encoded with sn3dHarmonics(1, direction).
//
// Late reverberation, per octave band b (the nine S3A bands) and per channel: independent
// Gaussian noise, band-limited by BandFilterBank's band-b response, of unit mean square,
// under the band's envelope (late_envelope.h: zero before onset_s, a ramp over the band's
// attack time, linear as in the VISR renderer or raised-cosine, then the decay; level_b at
// the mixing time and exp(-delta_b (t - t_mix)) after it). This is exactly the model late_reverb.h measures: the band's
// W has mean square level_b^2 at the mixing time and decays with delta_b. Channels Y, Z, X
// carry 1/3 of W's energy each, independent of W and of each other: a diffuse field in SN3D.
//
// Two corrections make the late part reproduce those numbers when analysed again (the
// round trip estimateLateReverb(resynthesizeRsao(rsao)) returns rsao's late part):
//   - Band leakage: the analysis bands overlap over their crossovers, so analysis band b
//     also sees 5-9 % of each neighbour's noise; the noise powers are M^-1 times the
//     targets, M the realised leakage matrix. Where that asks for negative power (a band
//     that falls more than about 10 dB below a neighbour within its first 20 dB of decay)
//     it is zero, and the band comes out decaying a little slower than asked: +7 % T60 at
//     16 kHz for 0.4 s there, 6 dB below an 8 kHz band of 0.6 s. Parameters measured with
//     this same filter bank should rarely ask for that: their bands already hold the
//     neighbours' leakage.
//   - Envelope matching: one draw of Gaussian band noise has a Rayleigh envelope whose slow
//     wander scatters a narrow band's decay by far more than the model says (ISO 3382-2
//     A.2: +-20 % T20 at 63 Hz for T = 1 s). The late part is analysed as the estimator
//     will analyse it and each band's amplitude corrected so that its short-time mean
//     square, smoothed over max(match_bandwidths / bandwidth, match_min_span_s) (90 ms at
//     63 Hz, 20 ms from 500 Hz up), follows the model; match_passes passes. Within that
//     span the signal stays noise.
// Both are the resynthesis' business only: the VISR renderer, given the same numbers, adds
// plain band-filtered noise.
//
// Deterministic: the same Rsao, options and seed give the same samples.
#include <cstdint>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/rsao/late_envelope.h"
#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {


struct ResynthesisOptions {
  std::uint32_t seed = 1;
  // Length of the output; 0 takes Rsao::duration_s, and when that is 0 too, the mixing
  // time plus the longest band T60 (or the last reflection's response, if later).
  double duration_s = 0.0;
  // D, the length of the Hamming window centred on the arrival over which the estimator
  // measured EarlyReflection::level (EarlyReflectionOptions::analysis_window_s).
  double analysis_window_s = 0.002;
  // A reflection filter's response is kept this long (its ringing past it is cut).
  double reflection_response_s = 0.020;
  OnsetRamp onset_ramp = OnsetRamp::kLinear;
  bool include_early = true;  // direct sound and early reflections
  bool include_late = true;
  // Envelope matching of the late part (see above); 0 passes leaves plain band noise
  // under the leakage-corrected envelopes.
  int match_passes = 3;
  double match_bandwidths = 4.0;
  double match_min_span_s = 0.020;
};

// Throws InputError for an Rsao it cannot render: non-finite or negative times or levels,
// a late part whose band count is not nine, a non-positive decay constant, an onset after
// the mixing time, an unstable reflection filter, or an output longer than 60 s.
AudioBuffer resynthesizeRsao(const Rsao& rsao, const ResynthesisOptions& options = {});

}  // namespace room_reverb::core
