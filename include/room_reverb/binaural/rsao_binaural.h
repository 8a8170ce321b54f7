#pragma once
// The binaural room impulse response (BRIR) of an RSAO: the parametric route of Coleman et
// al. (S3A object-based reverb) and Remaggi et al. as a listener hears it over headphones,
// straight from the object's parameters rather than through an ambisonic decoder.
//
// Output: two channels, left then right, at 48 kHz (the HRTF set's rate, which must be 48
// kHz: load the set with HrtfSet::loadSofa(path), which resamples to 48 kHz by default).
//
// Direct sound and early reflections: each the same mono tap as the W channel of
// resynthesizeRsao (reflection_tap.h: fractional delay, LPC / second-order-section shape,
// level under the estimator's Hamming window) convolved with the HRIR pair of its direction
// (HrtfSet::interpolated), so it arrives at its time of arrival plus the HRIRs' own onset,
// from its direction. The HRIRs are used as they are: their leading delay is not removed.
//
// Late reverberation: a diffuse field as these HRTFs hear it (Menzer & Faller, "Binaural
// reverberation using a modified Jot reverberator with frequency-dependent interaural
// coherence matching", AES 126th Convention, 2009; Borss & Martin, "An improved parametric
// model for perception-based design of virtual acoustics", AES 35th Conference, 2009: the
// ears' late signals need the diffuse-field coherence and power of the listener's HRTFs).
// Each ear is a resynthesis of the late part (late_noise.h: the resynthesis' band noise,
// leakage correction and envelope matching), with two changes:
//   - its stationary band noises are mixed from two independent draws n1, n2 before they
//     are shaped, symmetrically, so that neither ear is favoured:
//         left_b = a_b n1_b + s_b n2_b,  right_b = a_b n1_b - s_b n2_b,
//         a_b = sqrt((1 + c_b) / 2),     s_b = sqrt((1 - c_b) / 2),
//     whose coherence is a_b^2 - s_b^2 = c_b, the set's diffuse-field coherence in octave
//     band b (diffuseFieldCoherence). The draws are first flattened to unit short-time
//     power (LateNoiseSynthesizer::flattenEnvelopes), so that chance differences between
//     them early in the decay, which weights its first tenth of a second, move the
//     coherence less: its scatter over seeds at 500 Hz (T60 1.2 s) falls from 0.08 to 0.05;
//   - its band targets are the W targets times P_ear,b, the set's diffuse-field power
//     response averaged over band b (diffuseFieldSpectrum), so that each ear's band has
//     mean square P_ear,b level_b^2 at the mixing time and decays with delta_b: what an
//     omnidirectional pressure of level_b in a diffuse field gives at that ear.
// Mixing before shaping keeps the envelopes exact (a mixing filter applied afterwards
// would smear the onset backwards). Coherence and ear power are constant within each
// octave band, as the object's other late parameters are. The late field is diffuse, so
// the head's orientation leaves it unchanged.
//
// Deterministic: the same Rsao, HRTF set, options and seed give the same samples.
#include <Eigen/Core>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/binaural/diffuse_field.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/rsao/rsao.h"
#include "room_reverb/rsao/rsao_resynthesis.h"

namespace room_reverb::core {

struct RsaoBinauralOptions {
  // Seed, length, analysis window, reflection response, onset ramp, which parts to render
  // and the late part's envelope matching: as for resynthesizeRsao (rsao_resynthesis.h).
  // The late part's two noises are the seed's first two draws (late_noise.h).
  ResynthesisOptions resynthesis;
  // The listener's head orientation in the frame of the RSAO's directions (the rig's): the
  // rotation taking head-frame vectors to rig-frame vectors (its columns are the head's x,
  // y, z axes in rig coordinates), as a tf lookup of "head" in "rig" gives it. A reflection
  // from rig direction d is heard from head direction head_in_rig^T d. Example: a head
  // turned 90 degrees to the left (yaw +pi/2 about z) hears a reflection from the rig's +y
  // straight ahead. Same convention as headTrackingRotation (ambisonics/rotation.h).
  Eigen::Matrix3d head_in_rig = Eigen::Matrix3d::Identity();
};

// Throws InputError for an Rsao with no direct sound (no reflections), an HRTF set not at
// 48 kHz, a head_in_rig that is not a proper rotation, and whatever resynthesizeRsao
// refuses (non-finite or negative times or levels, non-finite directions, a late part
// without its nine bands, unstable filters, an output longer than 60 s).
AudioBuffer renderRsaoBinaural(const Rsao& rsao, const HrtfSet& hrtfs, const RsaoBinauralOptions& options = {});

// The same with the set's diffuse-field spectrum computed beforehand (diffuseFieldSpectrum
// of this set): for many renders with one set, as the spectrum of a dense set (the KU100's
// 2354 directions) takes longer than a whole late part. InputError for an empty spectrum.
AudioBuffer renderRsaoBinaural(const Rsao& rsao, const HrtfSet& hrtfs, const DiffuseFieldSpectrum& diffuse_field,
                               const RsaoBinauralOptions& options = {});

}  // namespace room_reverb::core
