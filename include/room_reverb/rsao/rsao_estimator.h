#pragma once
// The whole RSAO estimator (Remaggi et al., section 2.1): a measured B-format room impulse
// response in, a reverberant spatial audio object out.
//
//   1. the input is checked, converted to AmbiX and resampled to 48 kHz (the RSAO time
//      base); a stated convention that the channel energies contradict is a warning;
//   2. the direct sound is located (ISO 3382-1 onset on W) and must stand out of what
//      follows it (min_direct_prominence_db), else there is nothing to anchor the object;
//   3. the mixing time is the first time after it that W's normalised echo density reaches
//      1 (echo_density.h), unless the caller fixes it;
//   4. the direct sound and the early reflections up to the mixing time (early_reflections.h);
//   5. the late reverb per octave band from the mixing time on, its onset ramp starting at
//      the first reflection (late_reverb.h), each band's ramp length fitted so that the
//      early part holds the measured early energy (onset_ramp_fit.h).
#include <optional>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/rsao/early_reflections.h"
#include "room_reverb/rsao/echo_density.h"
#include "room_reverb/rsao/late_reverb.h"
#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

struct RsaoOptions {
  // Its mixing_time_s is ignored: the early part ends at the mixing time found below.
  EarlyReflectionOptions early;
  // A fixed mixing time (s from the first sample), instead of the echo-density estimate.
  std::optional<double> mixing_time_s;
  EchoDensityOptions echo_density;
  MixingTimeOptions mixing;
  LateReverbOptions late;
  // The direct sound's peak power over the mean power of the 50 ms after it (from 2.5 ms
  // on). Measured RIRs bundled with the project range from 20 to 38 dB;
  // a decaying noise burst with no direct sound reads 10-12 dB (a Gaussian crest factor).
  double min_direct_prominence_db = 15.0;
  // Each band's onset ramp fitted to the measured early energy (onset_ramp_fit.h); false
  // keeps the paper's single ramp from the first reflection to the mixing time.
  bool fit_onset_ramps = true;
};

// InputError naming the bad field unless the options are usable.
void validateRsaoOptions(const RsaoOptions& options);

// `bformat`: a first-order B-format RIR in `format` (four channels; AmbiX input of higher
// order has (N+1)^2 channels and its first four are used), any rate the project accepts.
// Throws InputError for a wrong channel count, non-finite samples, silence, no clear direct
// sound, or too little signal after the mixing time (0.1 s). Problems that leave a usable
// estimate (clipping, a doubtful format, a mixing time from the fallback rule, resampling)
// are listed in Rsao::warnings; unreliable late bands say why in their own reason.
Rsao estimateRsao(const AudioBuffer& bformat, AmbisonicFormat format, const RsaoOptions& options = {});

}  // namespace room_reverb::core
