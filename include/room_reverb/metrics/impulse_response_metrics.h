#pragma once
// The metrics job as the tool and the node run it: one channel of a multichannel
// impulse response, brought to the internal 48 kHz rate, analysed per band.
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"

namespace room_reverb::core {

// Validates the buffer (InputError on a bad rate, NaN/Inf, silence, too few samples, a
// channel index out of range), resamples to 48 kHz if needed and analyses `channel`.
// Bands above the original Nyquist frequency are reported as unavailable.
MetricsReport analyseImpulseResponse(const AudioBuffer& rir, int channel,
                                     MetricsOptions options = {});

}  // namespace room_reverb::core
