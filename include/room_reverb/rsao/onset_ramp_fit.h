#pragma once
// Fitting each late band's early course to the measured early energy (this project's
// extension of the RSAO; late_envelope.h).
//
// The paper's RSAO carries the early part as a few discrete reflections, each a tap of
// D = 2 ms, plus one linear ramp of the late noise from the first reflection to the mixing
// time. On measured rooms that leaves much of the early energy out: arrivals too weak or
// too dense to be picked, the diffuse energy that builds up before the mixing time, and
// the low-frequency part of each tap (a 2 ms window resolves nothing below about 1 kHz, so
// the order-9 LPC spreads the tap's energy evenly there). On the bundled RIRs the
// resynthesised W channel had 2-9 dB less band energy between the direct sound and the
// mixing time than the measurement, and its EDT came out up to 37 % long.
//
// The fit gives band b the onset level g_b for which the taps plus the late envelope hold
// the measured band energy from 1 ms before the direct sound to the mixing time:
//
//   E_taps,b + sum_t e_b(t)^2 = E_measured,b       (sums over that span, unit-mean-square noise)
//
// e_b moving geometrically from g_b at the onset to level_b at the mixing time. Where the
// paper's ramp (with the taps) already holds the measured energy, the band keeps it
// (g_b = 0). The course after the mixing time, the measured decay and level, is untouched.
#include <vector>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

struct OnsetRampFitOptions {
  double analysis_window_s = 0.002;  // D of the early estimate (how the taps' levels were measured)
  double max_onset_gain_db = 40.0;   // g_b at most this far above level_b
  double course_extension_s = 0.05;
};

// Sets rsao.late.bands[b].onset_level from the measured W channel (48 kHz, the RIR the Rsao
// was estimated from). Does nothing when the late part has no bands or no span.
void fitOnsetRamps(const std::vector<float>& w_channel_48k, Rsao& rsao, const OnsetRampFitOptions& options = {});

// Reflections added to an RSAO after its onsets were fitted (the ones a room model
// completes, listener_translation.h) bring early energy the fitted course already holds,
// since it was fitted to the measured early energy, theirs included. Each band's course
// gives it up: its onset level is set so that the envelope between the first reflection
// and the course's end holds E_late,b - E_added,b, E_added,b what the added taps bring to
// the band over that span as the resynthesis plays them beside the RSAO's own (the band
// energy of all the taps less that of the RSAO's alone: close taps add coherently in the
// low bands), as fitOnsetRamps would have fitted it had those taps been measured. Where a band's course cannot give that much (it would fall
// below max_onset_gain_db under its level), the added reflections are too loud for the
// measurement: their levels are scaled down together until every band of 125 Hz-4 kHz can
// (the bands where both the taps' spectra and the late levels are well estimated; the
// others give what they can). Returns that gain (1 when none is needed). Does nothing, and
// returns 1, without added reflections, late bands or an onset span.
double yieldOnsetEnergy(std::vector<EarlyReflection>& added, Rsao& rsao, const OnsetRampFitOptions& options = {});

}  // namespace room_reverb::core
