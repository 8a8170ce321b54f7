#pragma once
// A linear-phase FIR low-pass, for the ITU-R BS.1534-3 anchors of listening tests (the
// reference low-passed at 3.5 kHz, and at 7 kHz for the mid anchor).
//
// Why a long windowed sinc rather than an IIR filter: an anchor must remove what lies
// above its cutoff (a listener who still hears 6 kHz in the "3.5 kHz" anchor does not
// hear the anchor the recommendation means), and it must stay time-aligned with the
// stimulus it came from, so that switching between them at the same position sounds no
// jump. A Blackman-windowed sinc of 1201 taps at 48 kHz falls from -6 dB at the cutoff to
// below -70 dB about 110 Hz higher, with exactly linear phase whose delay is taken out.
#include <cstddef>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

// Taps of the anchor filters at 48 kHz: transition band about 220 Hz wide (5.5 fs / N for
// a Blackman window), stopband below -70 dB.
constexpr std::size_t kAnchorLowpassTaps = 1201;

// The Blackman-windowed sinc: `taps` (odd) coefficients, amplitude 0.5 (-6 dB) at
// `cutoff_hz`, unit gain at 0 Hz, symmetric about the middle tap. InputError for an even
// or zero tap count or a cutoff outside (0, Nyquist).
std::vector<float> windowedSincLowpass(double cutoff_hz, double sample_rate_hz, std::size_t taps);

// Every channel filtered by windowedSincLowpass and advanced by the filter's delay
// ((taps - 1) / 2 samples), so that the output lines up with the input sample for sample.
// The output keeps the filter's ringing after the last input sample: frameCount() +
// (taps - 1) / 2 frames. What the filter would put before the first input sample (the
// pre-ringing of an onset at the very start) is dropped. InputError for an invalid buffer.
AudioBuffer lowpassFiltered(const AudioBuffer& audio, double cutoff_hz, std::size_t taps = kAnchorLowpassTaps);

}  // namespace room_reverb::core
