#pragma once
// How many rays the fast mode's decay needs, and where it listens. Its pilot's energy in
// flight, what all rays carry through the room over time (RayTracingResult::
// energy_in_flight), gives a smooth decay from few rays; its seed spread falls
// with the ray count and depends on the room: in BRAS CR2, whose walls
// scatter, 2000 rays give T20 as steady as 8000 (1-2 % between seeds, the synthesis's own
// noise), while a room whose late sound rides on a few grazing paths between an absorbing
// floor and ceiling spreads by 5-17 % at 8000. So a pilot of a few rays comes first, in
// batches, each batch's fall giving one decay rate per band: when every band from 125 Hz to
// 4 kHz knows its mean rate within a tolerance (the standard error over the batches), the
// pilot is the decay; otherwise one run of as many rays as a preview's budget of
// reflections allows, at most the fast mode's ray count, heard at a track receiver near
// the listener. Where the pilot does not settle
// the long-lived energy rests on few paths and its estimate is heavy-tailed: ten seeds in
// a carpeted room spread T20 by 5-11 % at 8000 rays, 4-8 % at 32 000 and 1-4 % at 64 000
// (docs/simulation.md), so the run takes all the rays the budget buys.
#include <memory>
#include <optional>
#include <vector>

#include "room_reverb/acoustics/ray_tracer.h"

namespace room_reverb::core {

struct FastRayOptions {
  // The standard error of the batches' mean decay rate, relative to it, that every band
  // from 125 Hz to 4 kHz must reach (T20 is one over the rate, so its error is the same
  // share). 0: exactly the fast mode's ray count, in one run. The pilot's standard error
  // is 0.5-1.3 % in BRAS CR2 and 0.6-0.9 % in a hard church; 3.1-12.6 % in the rooms whose
  // late sound rides on grazing paths (scripts/fast-mode-check's rooms, four seeds each):
  // 2 % stops the first and leaves the others the full run, with a margin on both sides.
  double rate_tolerance = 0.02;
  std::size_t min_rays = 2000;  // the pilot's rays (four batches: a spread to go by)
  std::size_t batch_rays = 500;
  // The reflections the run after an unsettled pilot may cost, at the pilot's reflections
  // per ray: 3.2 million is 64 000 rays in the carpeted room of scripts/fast-mode-check
  // (0.48 s with the tool), 18 000 in its hall, whose rays live three times as long.
  double reflection_budget = 3.2e6;
  // That run's receiver: the track the rays run within this radius (m) of the listener
  // (RayTracingOptions::track_radius_m), which the fast mode plays as its late part.
  // Where the pilot does not settle the late field is not diffuse, and the energy in
  // flight over the volume misses what the listener hears: in a 30 m corridor the energy
  // reaches the listener in pulses along its length, and in every room it misses the
  // diffuse energy of the first reflections (docs/simulation.md).
  double track_radius_m = 2.0;
  // That run's launch directions: this share of its rays follows where the pilot's late
  // energy was launched (launch_density.h: per cell of the sphere, the mean over the bands
  // 125 Hz-4 kHz of the cell's share of the energy in flight while it falls from 5 to 25
  // dB down), the rest is uniform. 0: uniform, as the accurate mode launches.
  double late_launch_mixture = 0.5;
};

// The decay rate (dB/s, negative) of one band's energy in flight: the least-squares line
// through its level from 5 to 25 dB below where it starts, the range T20 reads; where it
// falls less than 25 dB within the trace, from 5 dB down to the lowest level it reaches
// if that spans 10 dB. None where it falls less.
std::optional<double> energyDecayRateDbPerS(const std::vector<OctaveBandValues>& energy_in_flight, int band,
                                            double bin_s);

struct FastModeTrace {
  // When the pilot settled: its energy in flight, the mean over its batches, and the same
  // without the image sources' paths; empty otherwise.
  std::vector<OctaveBandValues> energy_in_flight;
  std::vector<OctaveBandValues> late_energy_in_flight;
  RayTracingStats stats;  // summed over the batches
  std::size_t batches = 0;
  // Otherwise: the track receiver of the run that follows (or of the one run with a rate
  // tolerance of 0), which records no energy in flight.
  std::optional<EnergyHistogram> receiver;
  // The density that run's rays were launched from (null: uniform).
  std::shared_ptr<const LaunchDensity> launch_density;
};

// The fast mode's rays: `rays` as the fast mode sets them up (energy in flight recorded):
// the pilot (options.min_rays in batches, batch b > 0 with a seed of its own drawn from
// rays.seed and b) when it knows every band's rate, else one run (its launch density drawn
// from the pilot's late energy, options.late_launch_mixture) with rays.seed of
// `max_rays` or, when that would cost more than options.reflection_budget at the pilot's
// reflections per ray, of as many as it buys (never fewer than the pilot's), with the
// track receiver of options.track_radius_m. With a rate tolerance of 0, exactly `max_rays`
// in one run. InputError for a zero ray count or batch, or a track radius not above 0.
FastModeTrace traceFastModeDecay(const AcousticScene& scene, const Eigen::Vector3d& source,
                                 const Eigen::Vector3d& listener, const PropagationModel& model,
                                 const RayTracingOptions& rays, std::size_t max_rays, const FastRayOptions& options);

}  // namespace room_reverb::core
