#pragma once
// The early part of the RSAO estimator (Remaggi et al., section 2.1): from a first-order
// B-format room impulse response, the direct sound and the early reflections, each with
// its time of arrival, level, direction and all-pole spectral shape.
#include <cstddef>
#include <optional>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/rsao/group_delay_onsets.h"
#include "room_reverb/rsao/lpc.h"
#include "room_reverb/rsao/matched_arrivals.h"
#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

enum class ReflectionSelection {
  kStrongest,            // the max_reflections strongest
  kAboveLevelThreshold,  // every one within level_threshold_db of the direct sound (at most max_reflections, strongest first)
};

enum class DirectionMethod {
  kClosedForm,  // exact maximum of the steered cardioid's energy (direction_of_arrival.h)
  kGridSearch,  // the paper's search over a sphere grid of step grid_step_rad
};

enum class OnsetMethod {
  // The default: matching pursuit against the direct sound and low-passed copies of it,
  // over all four channels, each arrival subtracted before the next is sought
  // (matched_arrivals.h); directions from each arrival's own projection; each
  // reflection's level is its own amplitude in W (the direct sound's is its window's, as
  // the paper's); the max_reflections kept are the strongest by that amplitude. It
  // resolves close pairs, arrivals on the direct sound's tail and dull reflections the
  // paper's onsets miss (docs/rsao.md: held-out recall 100 % against 66 %).
  kMatchedPursuit,
  // The paper's, for comparison: group-delay zero crossings of W (group_delay_onsets.h),
  // directions from the steered cardioid over the analysis window.
  kGroupDelay,
};

struct EarlyReflectionOptions {
  OnsetMethod onset_method = OnsetMethod::kMatchedPursuit;
  MatchedArrivalOptions matched;
  // End of the early part, from the first sample of the RIR (the caller's mixing time).
  // When not given: the direct sound plus default_early_duration_s.
  std::optional<double> mixing_time_s;
  double default_early_duration_s = 0.08;
  // The direct sound is the first strong arrival: the first sample within this many dB of
  // the peak (ISO 3382-1 annex A, as findDirectSoundOnset), then the earliest group-delay
  // arrival within [-0.5, +1] ms of it whose local energy is within this many dB of the
  // strongest arrival there.
  double direct_onset_threshold_db = 20.0;
  GroupDelayOnsetOptions onsets;
  // D, the Hamming window over which level, direction and spectrum of each arrival are
  // taken. 2 ms: long enough to hold the main lobe of a reflection low-passed by absorbing
  // walls (the energy of a pulse with a few kHz of bandwidth lies within +-0.3 ms) and to
  // give the order-9 LPC 96 samples, short enough that an arrival 1 ms away falls on the
  // window's 0.08 edge (-22 dB in energy) and does not bend the direction estimate. (On
  // the synthetic rooms of the tests 1 to 2.5 ms all meet the accuracy targets; from 3 ms
  // on, neighbours inside the window start to bend directions past 5 degrees.)
  double analysis_window_s = 0.002;
  // With kGroupDelay onsets; matching pursuit takes each direction from the arrival's own
  // projection on its atom.
  DirectionMethod direction_method = DirectionMethod::kClosedForm;
  double grid_step_rad = 3.14159265358979323846 / 180.0;  // 1 degree
  int lpc_order = kDefaultLpcOrder;
  // The window resolves no spectral detail finer than about 1/D (500 Hz at 2 ms): below
  // that the segment's spectrum is mostly its neighbours' low frequencies, which a window
  // holding several arrivals adds coherently, so the paper's fit gives every tap of a dense
  // early part too much low-frequency energy (the development shoeboxes of
  // reflection_rooms.h, whose reflections are flat: +2.1, +2.0 and +1.7 dB at 125, 250 and
  // 500 Hz in the median tap). The fit takes the segment's power spectrum held at its value
  // at lpc_flat_below_hz below it instead (this project's extension: +0.6, +0.6 and +0.4 dB;
  // docs/rsao.md). Unset: 1 / analysis_window_s; 0: the paper's fit of the whole segment.
  std::optional<double> lpc_flat_below_hz;
  double speed_of_sound_m_s = 343.0;
  // The direct sound's distance [m] when the source's position is known (e.g. from the
  // measurement's positions). Without it: c times the direct sound's time of arrival,
  // which takes the RIR to start at the emission (a measurement system's latency or a
  // trimmed RIR moves every image source by c times that offset).
  std::optional<double> direct_distance_m;
  ReflectionSelection selection = ReflectionSelection::kStrongest;
  // Early reflections kept, not counting the direct sound (the result has at most
  // max_reflections + 1 entries). 40: matching pursuit reports about 20 real arrivals in
  // the first 30 ms of a small room (docs/rsao.md), and with 20 kept the weakest
  // resolvable ones of the held-out rooms are dropped (recall 93 % against 100 %).
  std::size_t max_reflections = 40;
  // For kAboveLevelThreshold: 20 log10(A_k / A_0) must be at least this.
  double level_threshold_db = -20.0;
};

// InputError naming the bad field unless the options are usable.
void validateEarlyReflectionOptions(const EarlyReflectionOptions& options);

// reflections[0] is the direct sound, the rest follow by time of arrival. Level A_k is
// sqrt(E_k), E_k the energy of W times the Hamming window of length D centred on the
// arrival; distance is the direct sound's distance plus speed_of_sound times the delay
// after it; confidence the window's directness. Throws InputError for fewer than 4 channels, a rate other than 48 kHz,
// NaN or infinite samples, a silent W channel, a response shorter than 10 ms or than
// the analysis window, or bad options.
std::vector<EarlyReflection> estimateEarlyReflections(const AudioBuffer& ambix_first_order_48k,
                                                      const EarlyReflectionOptions& options = {});

}  // namespace room_reverb::core
