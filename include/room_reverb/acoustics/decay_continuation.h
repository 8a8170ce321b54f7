#pragma once
// Continuing a band's late decay analytically once the ray tracing has established it.
//
// The energy that all rays still carry through the room (the energy in flight) is a
// smooth curve even at a few thousand rays, since every ray counts at every moment. Once
// a band's curve has fallen far and its last stretch is straight in dB, the rest of the
// band's late response is that straight line: tracing on only adds reflections that
// draw it again, with Monte-Carlo noise. Where the last stretch still bends (coupled
// volumes, grazing paths between absorbing floors and ceilings, whose slower population
// takes over late), the tracing must go on, and does.
#include <optional>
#include <vector>

#include "room_reverb/acoustics/energy_histogram.h"

namespace room_reverb::core {

// ln E(t) = ln_energy_at_zero + rate_per_s t (rate < 0).
struct EstablishedDecay {
  double ln_energy_at_zero = 0.0;
  double rate_per_s = 0.0;
  double fitted_from_s = 0.0;  // the start of the stretch its line was fitted on
  double energyAt(double t_s) const;
};

struct DecayContinuationOptions {
  // The band must have decayed this far (dB) below its launch energy in flight. Whatever
  // the receiver's decay measures read above that comes from the traced response: EDT
  // (10 dB) and C80 are traced, T20's range (5-25 dB down) as far as the energy in flight
  // has fallen, T30's last 10 dB may be continued. On BRAS CR2, with slices a quarter of
  // the elapsed time apart, 25 dB traces 47 million reflections per 100 000 rays where
  // 30 dB traces 62 million, with every octave's mean T20 over three seeds within 0.1 JND
  // of 30 dB's and EDT, C80 and D50 unchanged; in four rooms with grazing paths (eight
  // seeds each), whose decays bend and are traced to the end, within 0.03 JND. 20 dB
  // (37 million) moves CR2's 125 Hz T20 by 1 %. With each band stopped within a slice of
  // its own 25 dB (the tracer's slices), 43 million, T20 within 0.13 JND of tracing to
  // the end (docs/simulation.md).
  double decayed_db = 25.0;
  // The last `straight_span_db` of that fall are fitted with a line in two halves. The
  // change of slope between them, carried on while the later half's slope falls another
  // `bend_horizon_db`, must part from that line by at most `bend_db`; the later half's
  // line is continued. On BRAS CR2 the bands bend by 0.2-0.4 dB by this measure once
  // 30 dB down; in a room with carpet and ceiling tiles between hard walls (whose grazing
  // paths outlive the rest) the 2 kHz band bends by 2-8 dB there; a check of the halves'
  // slopes alone (10 % apart at most) lets it through and leaves T20 9 % short.
  double straight_span_db = 15.0;
  double bend_horizon_db = 15.0;
  double bend_db = 0.5;
  // The energy in flight over that stretch must also lie within this RMS (dB) of one
  // line. On BRAS CR2 it does within 0.02 dB at 30 000 rays; in a room with carpet and
  // ceiling tiles between plaster walls the 1 and 2 kHz bands scatter by 0.08-0.4 dB
  // (their late energy rides on a few grazing paths), and continued where the halves
  // happened to agree they come out 2-6 % short in T20.
  double scatter_db = 0.05;
};

// The decay line of one band's energy in flight, when it is established by the first
// `complete_bins` bins (width bin_s; energy averaged over each bin, launch energy at bin
// 0); nullopt while it is not.
std::optional<EstablishedDecay> establishedDecay(const std::vector<double>& energy_in_flight, std::size_t complete_bins,
                                          double bin_s, const DecayContinuationOptions& options);

// The receiver's energy in `band` from `from_s` on, as the decay line scaled to the
// histogram's own level over [window_from_s, from_s): the share of the room's energy that
// reaches the receiver (its diffuse-field coupling) and the mean direction it arrives
// from are measured there and held. Bins from `from_s` on are replaced.
void continueDecay(EnergyHistogram& histogram, int band, double window_from_s, double from_s, const EstablishedDecay& line);

}  // namespace room_reverb::core
