#pragma once
// Times of arrival of the direct sound and the early reflections by the DYPSA idea
// (Naylor et al. 2007, "Estimation of glottal closure instants in voiced speech using the
// DYPSA algorithm"; used on room impulse responses by Remaggi et al.): slide a short
// window along the omni (W) channel, take the segment's energy-weighted group delay
// relative to the window centre, and mark where it crosses zero going negative. An
// impulse at t0 makes that function t0 - n while it is inside the window (a line of slope
// -1), so the crossing sits on the impulse, to a fraction of a sample by interpolation.
// Noise and the tails of arrivals make crossings too, so candidates are then pruned (local
// energy against the direct sound's, a local energy peak, DYPSA's phase-slope test) and
// merged when closer than a minimum separation.
#include <cstddef>
#include <vector>

namespace room_reverb::core {

struct GroupDelayOnsetOptions {
  // Length of the sliding Hamming window. Shorter separates close arrivals better but
  // lets more noise through; 1 ms (49 samples at 48 kHz) holds the main lobe of a
  // reflection low-passed by absorbing walls with room to spare, and two arrivals 1 ms
  // apart are never in one window together.
  double window_s = 0.001;
  // Candidates closer than this are one arrival (the stronger is kept). Half the window:
  // a crossing further than that from a strong arrival no longer has it in its window.
  double min_separation_s = 0.0005;
  // A candidate's local energy (the window's energy around it) must be within this many dB
  // of the reference arrival's (the direct sound's).
  double relative_threshold_db = -40.0;
  // A candidate must carry a local energy peak: its local energy within peak_margin_db of
  // the largest local energy of the window centres within +-peak_neighbourhood_s. This
  // drops the crossings that the group delay makes in the quiet gaps beside a strong
  // arrival (its window then holds only the arrival's tail or noise), which a fixed
  // threshold cannot tell from weak reflections. Those centres' windows reach
  // peak_neighbourhood_s + window_s / 2 = 1 ms by default: an arrival with no neighbour of
  // comparable level (within 6 dB, or stronger) closer than 1 ms passes.
  double peak_neighbourhood_s = 0.0005;
  double peak_margin_db = 6.0;
  // DYPSA's phase-slope test (Naylor et al. 2007): across a true arrival d(n) falls with
  // slope -1, because the window slides past an impulse (or a tight cluster of them) that
  // dominates it. With other energy in the window the slope is about -(the arrival's
  // share of the window energy); in the smooth tails of low-frequency ringing and in noise
  // it is near 0. A candidate is kept only if |slope + 1| <= max_slope_deviation: 0.5
  // asks that the arrival carry about half of its window's energy or more.
  double max_slope_deviation = 0.5;
};

struct ArrivalCandidate {
  double time_s = 0.0;        // from the first sample of the signal, sub-sample resolution
  double local_energy = 0.0;  // sum of (w x)^2 over the group-delay window centred there
  double slope = 0.0;         // d(n+1) - d(n) across the crossing: -1 for an isolated impulse
};

// The energy-weighted group delay d(n) of the windowed segment centred on each sample n
// in [first_centre, end_centre), relative to the centre, in samples, with the segment's
// energy. Samples outside the signal count as zero.
struct GroupDelayFunction {
  double sample_rate_hz = 0.0;
  std::size_t first_centre = 0;
  std::vector<double> delay_samples;  // d(first_centre + i); 0 where the segment is silent
  std::vector<double> local_energy;   // sum_m w[m]^2 x[n+m]^2
};

GroupDelayFunction energyWeightedGroupDelay(const std::vector<float>& x, double sample_rate_hz,
                                            std::size_t first_centre, std::size_t end_centre,
                                            std::size_t window_length);

// Window length in samples for window_s at sample_rate_hz: odd (a centre sample) and >= 3.
std::size_t groupDelayWindowLength(double window_s, double sample_rate_hz);

// Every n with d(n) > 0 >= d(n+1), refined to the linear interpolation's zero, with the
// local energy interpolated there. In time order.
std::vector<ArrivalCandidate> negativeGoingZeroCrossings(const GroupDelayFunction& gd);

// Keeps candidates whose local energy is at least reference_energy * 10^(threshold_db/10)
// and that carry a local energy peak of `gd` (see the options), strongest first, dropping
// any closer than min_separation_s to one already kept. In time order.
std::vector<ArrivalCandidate> pruneCandidates(const std::vector<ArrivalCandidate>& candidates,
                                              const GroupDelayFunction& gd, double reference_energy,
                                              const GroupDelayOnsetOptions& options);

// InputError naming the bad field unless the options are usable.
void validateGroupDelayOnsetOptions(const GroupDelayOnsetOptions& options);

}  // namespace room_reverb::core
