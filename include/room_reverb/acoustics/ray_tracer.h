#pragma once
// Stochastic ray tracing for the late part (Krokstad et al. 1968; Vorländer 2008 ch. 11).
//
// Rays leave the source in stratified directions (weighted by its directivity) each
// carrying 1/N of a joule per band, or drawn from a launch density (launch_density.h) and
// weighted to undo it. At a wall a ray loses the absorbed share, then
// reflects specularly or diffusely (Lambert) with the probability given by the scattering
// coefficient: one or the other, never a blend of the two directions (a blend shortens
// the mean free path and the decay). Bands share a ray's path until their scattering
// coefficients make them choose differently; then the ray splits into one branch per
// choice (one uniform number per wall serves every band), so no band is reweighted.
// Faded branches play Russian roulette rather than meeting a hard energy floor.
//
// Receiver: the scattered share of each reflection goes to the receiver as "diffuse rain"
// (Schröder 2011): E (1 - alpha) s cos(theta) / (pi d^2) per unit area when the receiver is
// visible. Rays whose last reflection was specular are detected when they cross a sphere
// around the receiver (E / (pi r^2)); purely specular paths up to the image-source order
// are left out, since the image sources carry them.
#include <cstdint>
#include <memory>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/decay_continuation.h"
#include "room_reverb/acoustics/energy_histogram.h"
#include "room_reverb/acoustics/launch_density.h"
#include "room_reverb/acoustics/path_ledger.h"
#include "room_reverb/acoustics/propagation.h"

namespace room_reverb::core {

struct RayTracingOptions {
  std::size_t ray_count = 100000;
  double max_time_s = 2.0;          // rays stop here (and the histogram ends)
  double bin_s = 0.001;             // histogram resolution
  // Detection sphere of specular arrivals; 0: automatic (autoReceiverRadius).
  double receiver_radius_m = 0.0;
  // Crossings of the automatic sphere per millisecond that it is sized for. The spread
  // of late decay times between seeds falls with it: raise it with the ray count to make
  // more rays lower the spread rather than shrink the sphere (docs/diagnosis.md).
  double crossings_per_ms = 300.0;
  // > 0: the receiver is instead the track every ray runs inside a sphere of this radius
  // about the listener, its energy times the length run there over the sphere's free
  // volume (the fluence, which the crossings of the detection sphere also estimate), per
  // bin of the time it runs there. Every leg that passes near counts over its whole chord,
  // diffuse legs included (no diffuse rain then), and the sphere may reach through walls:
  // only its part inside the room counts. Specular paths up to image_source_order are left
  // to the image sources as with the sphere. The fast mode's receiver (room_simulation.h).
  double track_radius_m = 0.0;
  // A branch whose every band has fallen this far below its launch energy (air included)
  // plays Russian roulette: unbiased, and the faded paths stop costing reflections.
  double roulette_db = -60.0;
  int image_source_order = 3;       // specular-only paths up to this order are not counted (-1: count all)
  bool diffuse_rain = true;
  // Add to each reflection's scattering what its surface's finite size diffracts
  // (diffraction_scattering.h): d1 is the leg the ray arrives on, d2 the room's mean free
  // path 4V/S (the leg it leaves on is not known before the choice; in an open room, d1).
  bool diffraction_scattering = false;
  // Also sum the energy every ray carries through the room over time
  // (RayTracingResult::energy_in_flight): the room's own decay, which the fast mode's pilot
  // reads.
  bool record_energy_in_flight = false;
  // Stop tracing a band once its decay is established and continue it analytically
  // (decay_continuation.h): the rays are traced in slices of time, and after each slice
  // every band whose energy in flight has fallen `continuation.decayed_db` along a
  // straight line stops; its receiver energy from there on is that line at the level the
  // receiver had over the fitted stretch. Bands whose decay still bends are traced on.
  bool continue_established_decays = true;
  DecayContinuationOptions continuation;
  // Launch directions drawn from this density (launch_density.h) instead of uniformly,
  // each ray carrying its share of the emission times the uniform density over this one:
  // every expected energy is unchanged. The rays stay stratified (ray i takes the i-th of
  // `ray_count` equal steps of the density's cumulative over its zones), with azimuths on
  // the golden-angle sequence turned by one random offset per seed. Null: uniform, from a
  // Fibonacci sphere turned by one random rotation per seed.
  std::shared_ptr<const LaunchDensity> launch_density;
  // Also sum the energy in flight per launch cell (RayTracingResult::
  // energy_in_flight_by_launch_cell), which a density for a later run is drawn from.
  bool record_launch_cells = false;
  std::uint32_t seed = 1;
  int threads = 0;                  // 0: all hardware threads
};

struct RayTracingStats {
  std::size_t rays = 0;
  std::size_t reflections = 0;
  std::size_t leaked_rays = 0;      // left a closed room: a hole in the mesh
  std::size_t escaped_rays = 0;     // left an open room (no ceiling): expected
  std::size_t stopped_by_time = 0;
  std::size_t stopped_by_energy = 0;  // ended by Russian roulette
  std::size_t sphere_detections = 0;
  // Energy (J, per band) still carried by rays when they reached max_time_s, over the
  // energy emitted: 1 in a lossless closed room.
  OctaveBandValues energy_left_at_time_limit{};
  double receiver_radius_m = 0.0;   // the radius used (the track receiver's, with one)
  // Per band: the time from which its decay is continued analytically (the full duration
  // when it was traced to the end).
  OctaveBandValues traced_until_s{};
};

struct RayTracingResult {
  EnergyHistogram histogram;
  RayTracingStats stats;
  // With record_energy_in_flight: per histogram bin and band, the energy still travelling
  // in the room, averaged over the bin (J per J emitted; air included). It does not depend
  // on the listener: in a diffuse field the energy density anywhere is this over the
  // volume, and its course holds where the absorption sits (a ray between hard walls
  // keeps its energy longer than Eyring's mean absorption allows).
  std::vector<OctaveBandValues> energy_in_flight;
  // The same less what the specular paths up to image_source_order carry: the part the
  // image sources do not hold (a continued band's line is both).
  std::vector<OctaveBandValues> late_energy_in_flight;
  // With record_launch_cells: the energy in flight of the rays launched in each cell
  // (launchCellOf), per kLaunchCellBinS of time: element cell * bins + bin.
  std::vector<OctaveBandValues> energy_in_flight_by_launch_cell;
  // With a ledger budget: the paths, when they fit and could be kept (null otherwise).
  std::shared_ptr<const PathLedger> ledger;
};

// The time bins of RayTracingResult::energy_in_flight_by_launch_cell.
constexpr double kLaunchCellBinS = 0.025;

// Adds `part`'s counts (rays, reflections, leaked, escaped, stopped by time and by
// energy, sphere detections) to `total`'s.
void addRayCounts(RayTracingStats& total, const RayTracingStats& part);

// Radius of the detection sphere when none is given. Its crossings are the only estimate
// of specular energy after the image sources, and their count sets the seed-to-seed
// spread of late decay times in rooms with low scattering: about N pi r^2 c / V
// crossings per millisecond (N rays, volume V, no absorption). The radius gives
// `crossings_per_ms` (300 by default): in the sample room (89 m^3, low scattering) T20
// varied over seeds by 5-25 % with 35 per ms (100 000 rays, 0.3 m) and by 1.5-5 % with
// 300 per ms (0.5 m). At a fixed count more rays buy a smaller sphere, not a smaller
// spread (the rest of it, from the rays' paths, still falls). It is kept between 0.1 m
// and 1.5 m and within 90 % of the listener's distance to the nearest surface, so the
// sphere never pokes through a wall (crossings lost there would bias the energy low).
// Measured in docs/simulation.md and docs/diagnosis.md.
double autoReceiverRadius(const AcousticScene& scene, const Eigen::Vector3d& listener, std::size_t ray_count,
                          double speed_of_sound_m_s, double crossings_per_ms);

// `ledger_budget_bytes` > 0 keeps the paths (path_ledger.h) when they fit in that many
// bytes: a model that differs in absorption, air or directivity can then be replayed
// instead of traced. It is what the caller wants back, not physics, so it is no option
// (and not on the wire). No ledger is kept when a band was continued analytically (its
// later paths carry energy the receiver never saw) or with diffraction scattering (whose
// scattering depends on each path's legs).
RayTracingResult traceRays(const AcousticScene& scene, const Eigen::Vector3d& source,
                           const Eigen::Vector3d& listener, const PropagationModel& model,
                           const RayTracingOptions& options = {}, std::size_t ledger_budget_bytes = 0);

}  // namespace room_reverb::core
