#include "room_reverb/acoustics/ray_tracer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <thread>

#include "room_reverb/acoustics/air_loss_table.h"
#include "room_reverb/acoustics/triangle_visibility.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/hash_mix.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Rays are traced in fixed chunks, and chunk c always goes to thread c mod T: the same
// seed and thread count give the same sums in the same order.
constexpr std::size_t kRaysPerChunk = 256;
// A new leg starts this far off the wall, after the point is put back onto its plane.
constexpr double kSurfaceOffset_m = 1e-6;
// With continue_established_decays the rays are traced in slices at least this long, and
// the energy the walls and the roulette take, which decides which bands are established,
// is kept on this coarser grid (a line fitted over 15 dB of a 0.3 s T60 still spans 15
// bins of it).
constexpr double kSliceS = 0.025;
constexpr double kFlightBinS = 0.005;

// The tracer's random numbers are not drawn from a running generator but computed from
// (the branch's key, its reflection order, a slot): common random numbers. Two models that
// differ in one wall's material then trace the same paths with the same decisions until a
// decision itself changes (a roulette or scattering draw between the two models'
// thresholds), so the difference of their results, the held-out gain of a fitted cause in
// the diagnosis, carries only the noise of the paths that differ. With one generator per
// chunk of rays, the first extra draw would shift every later ray of the chunk onto new
// numbers, and a gain would be as noisy as the difference of two independent runs
// (measured in test_ray_tracer's OneSurfaceChangedAtTheSameSeedChangesLittleElse).
// The launch jitter is drawn at order 0 and the roulette only at reflections (order 1 and
// up), so the two share a slot without sharing a number.
enum DrawSlot : std::uint64_t { kLaunch = 0, kRoulette = 0, kScatter = 1, kLambertRadius = 2, kLambertAzimuth = 3, kSlots = 4 };

// Uniform in [0, 1) from the hash of (key, order, slot).
double keyedUniform(std::uint64_t key, int order, DrawSlot slot) {
  const std::uint64_t counter = static_cast<std::uint64_t>(order) * kSlots + slot;
  return unitFromBits(mixBits(key ^ mixBits(counter)));
}

constexpr double kGoldenFraction = 0.61803398874989484820;  // 1 / golden ratio

// Launch direction of ray `index` of `count`: stratified rather than independent. Ray i
// takes z uniform in the i-th of `count` equal-area zones (z = 1 - 2 (i + u) / count) and
// the golden-angle azimuth of a Fibonacci sphere; the whole set is turned by one random
// rotation per seed, so each ray's direction is still uniform on the sphere and every
// estimate stays unbiased. What stratification buys: the share of rays in any band of
// elevations is exact, not binomial. In a room with low scattering the late decay is
// carried by the few rays that graze the absorbing floor and ceiling, and their count
// drove most of the seed-to-seed spread of T20 (measured in docs/simulation.md).
Eigen::Vector3d stratifiedDirection(std::size_t index, std::size_t count, const Eigen::Matrix3d& rotation,
                                    double jitter) {
  const double z = 1.0 - 2.0 * (static_cast<double>(index) + jitter) / static_cast<double>(count);
  const double turns = static_cast<double>(index) * kGoldenFraction;
  const double phi = 2.0 * kPi * (turns - std::floor(turns));
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return rotation * Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
}

// A uniformly random rotation (Shoemake 1992, uniform unit quaternion) drawn from the seed.
Eigen::Matrix3d randomRotation(std::uint32_t seed) {
  std::seed_seq seq{seed, 0x5eedu, 0xa11u};
  std::mt19937_64 rng(seq);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double u1 = u(rng), u2 = 2.0 * kPi * u(rng), u3 = 2.0 * kPi * u(rng);
  const Eigen::Quaterniond q(std::sqrt(u1) * std::cos(u3), std::sqrt(1.0 - u1) * std::sin(u2),
                             std::sqrt(1.0 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
  return q.normalized().toRotationMatrix();
}

// Lambert (cosine-weighted) direction about the unit normal n from two uniform numbers.
Eigen::Vector3d lambertDirection(const Eigen::Vector3d& n, double u_radius, double u_azimuth) {
  const double r = std::sqrt(u_radius);
  const double phi = 2.0 * kPi * u_azimuth;
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d t1 = n.cross(helper).normalized();
  const Eigen::Vector3d t2 = n.cross(t1);
  return (r * std::cos(phi) * t1 + r * std::sin(phi) * t2 + std::sqrt(std::max(0.0, 1.0 - r * r)) * n).normalized();
}

// Per-material factors of one reflection, worked out once per traceRays call.
struct MaterialTerms {
  OctaveBandValues reflectance{};  // 1 - absorption
  OctaveBandValues scattering{};
};

// One branch of a ray: the bands in `bands` share this path (the others carry no energy).
struct RayBranch {
  Eigen::Vector3d position;
  Eigen::Vector3d direction;
  OctaveBandValues energy;
  BandMask bands = kAllBands;
  std::uint64_t key = 0;  // of its random numbers (keyedUniform)
  double travelled = 0.0;
  int order = 0;
  int launch_cell = 0;  // launchCellOf its ray's launch direction (recorded with record_launch_cells)
  bool specular_only = true;
  bool last_specular = true;
};

// Where one slice of the tracing ends: branches that reach `boundary_m` of travel wait in
// `parked` for the next slice. The energy in flight goes to `fine` (the result's, when
// recorded; may be null), and the energy each reflection and roulette takes from the
// rays to `losses` (per kFlightBinS of time; null without continuation). Bands continued
// analytically (not in `active`) reach the receiver no more, but their energies stay on
// the branches: the roulette and the splits decide as they would with every band traced,
// so the traced bands follow exactly the paths they would follow alone, and a branch is
// dropped only when it carries no traced band.
struct Slice {
  double boundary_m = std::numeric_limits<double>::infinity();
  BandMask active = kAllBands;
  std::vector<RayBranch>* parked = nullptr;
  std::vector<OctaveBandValues>* fine = nullptr;
  std::vector<OctaveBandValues>* late = nullptr;  // the same, without the image sources' paths
  std::vector<OctaveBandValues>* by_cell = nullptr;  // the same per launch cell (record_launch_cells)
  std::vector<OctaveBandValues>* losses = nullptr;
  std::vector<LedgerEvent>* ledger = nullptr;  // the chunk's, when paths are kept
};

// Appends one step to the slice's ledger, when it keeps one.
void note(const Slice& slice, LedgerEvent::Kind kind, std::uint32_t index = 0, double distance_m = 0.0,
          double factor = 0.0, const Eigen::Vector3d& direction = Eigen::Vector3d::Zero()) {
  if (!slice.ledger) return;
  LedgerEvent e;
  e.code = LedgerEvent::makeCode(kind, index);
  e.distance_m = distance_m;
  e.factor = static_cast<float>(factor);
  for (int i = 0; i < 3; ++i) e.direction[i] = static_cast<float>(direction[i]);
  slice.ledger->push_back(e);
}

// Calls add(k, share) for each of `bins` bins of `bin_m` that the stretch [from_m, to_m)
// of travel covers, `share` the part of the bin it covers.
template <class Add>
void forBinsCovered(double from_m, double to_m, double bin_m, std::size_t bins, Add add) {
  const double last_m = std::min(to_m, static_cast<double>(bins) * bin_m);
  if (!(last_m > from_m)) return;
  const auto first_bin = static_cast<std::size_t>(from_m / bin_m);
  const auto last_bin = std::min(bins - 1, static_cast<std::size_t>(last_m / bin_m));
  for (std::size_t k = first_bin; k <= last_bin; ++k) {
    const double lower = static_cast<double>(k) * bin_m;
    const double share = (std::min(last_m, lower + bin_m) - std::max(from_m, lower)) / bin_m;
    if (share > 0.0) add(k, share);
  }
}

struct Tracer {
  const AcousticScene& scene;
  const Eigen::Vector3d& source;
  const Eigen::Vector3d& listener;
  const PropagationModel& model;
  const RayTracingOptions& options;
  double receiver_radius_m;
  double ray_energy;
  std::vector<MaterialTerms> terms;       // per scene material
  std::vector<double> plane_offset;       // per triangle: normal . vertex0
  AirLossTable air;
  double bin_length_m;
  double roulette_level;  // J: below it a branch plays Russian roulette
  Eigen::Matrix3d launch_rotation;
  double launch_azimuth_offset = 0.0;  // with a launch density: the azimuths' turn, in turns
  std::uint64_t seed_key;  // every ray's key derives from it and the ray's index
  double loss_bin_m;        // kFlightBinS of travel
  double mean_free_path_m;  // 4V/S of a closed room, 0 for an open one
  bool tracking = false;      // the receiver is the track receiver (RayTracingOptions::track_radius_m)
  double track_weight = 0.0;  // then 1 / its free volume (m^-3)
  TriangleVisibility visibility;  // where on each triangle the listener is seen (the rain needs no ray)
  // With record_launch_cells: the air's loss at the middle of each bin of kLaunchCellBinS,
  // per band (kOctaveBandCount values a bin).
  std::vector<double> cell_air;

  Tracer(const AcousticScene& scene_, const Eigen::Vector3d& source_, const Eigen::Vector3d& listener_,
         const PropagationModel& model_, const RayTracingOptions& options_, double receiver_radius_m_,
         double ray_energy_, std::size_t bins)
      : scene(scene_), source(source_), listener(listener_), model(model_), options(options_),
        receiver_radius_m(receiver_radius_m_), ray_energy(ray_energy_),
        air(model_.air_attenuation_per_m, options_.bin_s * model_.speed_of_sound_m_s, bins) {
    for (const AcousticMaterial& material : scene.materials()) {
      MaterialTerms t;
      for (int b = 0; b < kOctaveBandCount; ++b) {
        t.reflectance[b] = 1.0 - material.absorption[b];
        t.scattering[b] = material.scattering[b];
      }
      terms.push_back(t);
    }
    const TriangleMesh& mesh = scene.mesh();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) plane_offset.push_back(mesh.normal(t).dot(mesh.vertices[mesh.triangles[t][0]]));
    bin_length_m = options.bin_s * model.speed_of_sound_m_s;
    if (options.record_launch_cells) {
      const auto cell_bins = static_cast<std::size_t>(std::ceil(options.max_time_s / kLaunchCellBinS));
      const double cell_bin_m = kLaunchCellBinS * model.speed_of_sound_m_s;
      for (std::size_t k = 0; k < cell_bins; ++k) {
        const double middle_m = (static_cast<double>(k) + 0.5) * cell_bin_m;
        for (int b = 0; b < kOctaveBandCount; ++b) cell_air.push_back(std::exp(-model.air_attenuation_per_m[b] * middle_m));
      }
    }
    loss_bin_m = kFlightBinS * model.speed_of_sound_m_s;
    mean_free_path_m = scene.closed() && scene.volumeM3() > 0.0 ? 4.0 * scene.volumeM3() / scene.surfaceM2() : 0.0;
    roulette_level = ray_energy * std::pow(10.0, options.roulette_db / 10.0);
    tracking = options.track_radius_m > 0.0;
    if (tracking) {
      const double volume = scene.freeVolumeInSphereM3(listener, options.track_radius_m);
      if (!(volume > 0.0)) throw InputError("the track receiver's sphere holds no free volume about the listener");
      track_weight = 1.0 / volume;
    } else if (options.diffuse_rain) {
      visibility = TriangleVisibility(mesh, listener);
    }
    launch_rotation = randomRotation(options.seed);
    launch_azimuth_offset = unitFromBits(mixBits(0xa21ull ^ static_cast<std::uint64_t>(options.seed)));
    seed_key = mixBits(0x7ace5eedull ^ static_cast<std::uint64_t>(options.seed));
  }

  // Arrival of `energy` in the bands of `bands` after `distance_m` scaled by `factor`,
  // with air. The other bands carry nothing here: they left the branch at a split, or
  // are continued analytically.
  void deposit(EnergyHistogram& histogram, const OctaveBandValues& energy, double distance_m, double factor,
               const Eigen::Vector3d& direction, BandMask bands) const {
    OctaveBandValues weight;
    air.loss(distance_m, factor, weight, bands);
    histogram.addBands(distance_m / model.speed_of_sound_m_s, energy, weight, direction, bands);
  }

  // The loudest band of `energy` after `travelled` metres of air, when it is below the
  // roulette level (the tables bound exp(-m travelled) from both sides and settle most
  // cases without an exp); nullopt when it is not.
  std::optional<double> loudestBelowRoulette(const OctaveBandValues& energy, BandMask bands, double travelled) const {
    const double* lower = air.lowerBound(travelled);
    double lo = 0.0;
    forEachBand(bands, [&](int b) { lo = std::max(lo, energy[b] * lower[b]); });
    if (lo >= roulette_level) return std::nullopt;
    double loudest = 0.0;
    forEachBand(bands, [&](int b) {
      loudest = std::max(loudest, energy[b] * std::exp(-model.air_attenuation_per_m[b] * travelled));
    });
    if (loudest >= roulette_level) return std::nullopt;
    return loudest;
  }

  // Russian roulette (Arvo and Kirk 1990): a branch whose loudest band is at L below the
  // roulette level T survives with probability L / T and then carries T, so every band's
  // expected energy is unchanged and no energy is lost to a cut-off. A faded branch costs
  // about 1 / (1 - reflectance) more reflections on average instead of running to the
  // time limit. True when the branch ends.
  // `loss`, when given, gets the energy the roulette takes (negative for the gain of a
  // survivor).
  // `gain` gets the survivor's energy factor (1 when the roulette was not played).
  bool rouletteEnds(RayBranch& ray, OctaveBandValues* loss, double& gain) const {
    gain = 1.0;
    const std::optional<double> loudest = loudestBelowRoulette(ray.energy, ray.bands, ray.travelled);
    if (!loudest) return false;
    const double survival = *loudest / roulette_level;
    if (keyedUniform(ray.key, ray.order, kRoulette) >= survival) {
      if (loss) forEachBand(ray.bands, [&](int b) { (*loss)[b] += ray.energy[b]; });
      return true;
    }
    gain = 1.0 / survival;
    forEachBand(ray.bands, [&](int b) {
      const double before = ray.energy[b];
      ray.energy[b] = before / survival;
      if (loss) (*loss)[b] += before - ray.energy[b];
    });

    return false;
  }

  // The slice's loss bin at `travelled_m` of travel.
  OctaveBandValues& lossAt(const Slice& slice, double travelled_m) const {
    return (*slice.losses)[std::min(slice.losses->size() - 1, static_cast<std::size_t>(travelled_m / loss_bin_m))];
  }

  static std::size_t flightBins(double duration_s) {
    return static_cast<std::size_t>(std::ceil(duration_s / kFlightBinS));
  }

  // Launches ray `index`. `pending` is the caller's scratch queue of branches (kept across
  // rays so the hot loop does not allocate per ray); empty on entry and on return.
  void traceRay(std::size_t index, std::vector<RayBranch>& pending, EnergyHistogram& histogram,
                RayTracingStats& stats, const Slice& slice) const {
    RayBranch start;
    start.position = source;
    start.key = mixBits(seed_key ^ mixBits(index));
    const double jitter = keyedUniform(start.key, 0, kLaunch);
    double weight = 1.0;
    if (options.launch_density) {
      const double turns = static_cast<double>(index) * kGoldenFraction + launch_azimuth_offset;
      const LaunchDensity::Draw draw = options.launch_density->draw(
          (static_cast<double>(index) + jitter) / static_cast<double>(options.ray_count), turns - std::floor(turns));
      start.direction = draw.direction;
      weight = draw.weight;
    } else {
      start.direction = stratifiedDirection(index, options.ray_count, launch_rotation, jitter);
    }
    if (slice.by_cell) start.launch_cell = launchCellOf(start.direction);
    const double gain = model.directivity.pressureGain(start.direction);
    start.energy.fill(ray_energy * gain * gain * weight);
    note(slice, LedgerEvent::kLaunch, 0, 0.0, ray_energy * gain * gain * weight, start.direction);

    ++stats.rays;
    if (slice.losses) {
      for (int b = 0; b < kOctaveBandCount; ++b) (*slice.losses)[0][b] -= start.energy[b];
    }
    pending.push_back(start);
    tracePending(pending, histogram, stats, slice);
  }

  void tracePending(std::vector<RayBranch>& pending, EnergyHistogram& histogram, RayTracingStats& stats,
                    const Slice& slice) const {
    while (!pending.empty()) {
      RayBranch branch = pending.back();
      pending.pop_back();
      traceBranch(branch, pending, histogram, stats, slice);
    }
  }

  // The track receiver's share of one leg of `leg_m` from the branch's position: its
  // energy times the length it runs inside the sphere over the sphere's free volume (a
  // fluence, as deposit's crossings give), at the time of the chord's middle. The chord
  // lasts at most 2 R / c (12 ms for 2 m); binning it whole costs one deposit per chord
  // instead of one per bin, with T20 and EDT unchanged (docs/simulation.md).
  void depositTrack(EnergyHistogram& histogram, const RayBranch& ray, double leg_m, BandMask bands) const {
    const double radius = options.track_radius_m;
    const Eigen::Vector3d to_listener = listener - ray.position;
    const double along = to_listener.dot(ray.direction);
    const double off_axis2 = to_listener.squaredNorm() - along * along;
    if (!(off_axis2 < radius * radius)) return;
    const double half_chord = std::sqrt(radius * radius - off_axis2);
    const double from_m = std::max(0.0, along - half_chord);
    const double to_m = std::min(leg_m, along + half_chord);
    if (!(to_m > from_m)) return;
    deposit(histogram, ray.energy, ray.travelled + 0.5 * (from_m + to_m), (to_m - from_m) * track_weight, -ray.direction,
            bands);
  }

  // Adds the branch's energy, air included, to every bin it spends travelling between
  // `from_m` and `to_m` along its path, weighted by the share of the bin it covers.
  void addInFlight(std::vector<OctaveBandValues>& in_flight, const RayBranch& ray, double from_m, double to_m) const {
    forBinsCovered(from_m, to_m, bin_length_m, in_flight.size(), [&](std::size_t k, double share) {
      const double* loss = air.atBin(k);
      for (int b = 0; b < kOctaveBandCount; ++b) in_flight[k][b] += share * ray.energy[b] * loss[b];
    });
  }

  // The same into the branch's launch cell's bins of kLaunchCellBinS (air at each bin's
  // middle).
  void addInFlightByCell(std::vector<OctaveBandValues>& by_cell, const RayBranch& ray, double from_m, double to_m) const {
    const std::size_t bins = by_cell.size() / kLaunchCells;
    const double bin_m = kLaunchCellBinS * model.speed_of_sound_m_s;
    OctaveBandValues* cell = &by_cell[static_cast<std::size_t>(ray.launch_cell) * bins];
    forBinsCovered(from_m, to_m, bin_m, bins, [&](std::size_t k, double share) {
      const double* loss = &cell_air[k * kOctaveBandCount];
      for (int b = 0; b < kOctaveBandCount; ++b) cell[k][b] += share * ray.energy[b] * loss[b];
    });
  }

  // Follows one branch until it leaves, runs out of time or energy. At a wall every band
  // of the branch goes diffuse when one uniform number u falls below its scattering
  // coefficient and specular otherwise: each band's choice has exactly its own
  // probability s_b, so no band is ever reweighted. Bands that disagree split the branch
  // (the specular part is queued in `pending`); since one u serves all bands, a split
  // separates the bands by scattering rank and a ray ends in at most one branch per band.
  // (Choosing for all bands with their mean scattering and reweighting each band by s/p
  // or (1-s)/(1-p), as before, is unbiased too, but the weights multiply over reflections
  // into a log-normal spread: T20 at 125 Hz varied by 25 % between seeds at 100 000 rays
  // in the sample room.)
  void traceBranch(RayBranch& ray, std::vector<RayBranch>& pending, EnergyHistogram& histogram,
                   RayTracingStats& stats, const Slice& slice) const {
    const double max_distance = options.max_time_s * model.speed_of_sound_m_s;
    const double r = receiver_radius_m;
    const double sphere_factor = 1.0 / (kPi * r * r);
    for (;;) {
      // A leg that starts before the slice's end is traced whole, so every bin before it
      // is complete when the slice ends.
      if (ray.travelled >= slice.boundary_m) {
        slice.parked->push_back(ray);
        note(slice, LedgerEvent::kPark);
        return;
      }
      const RayHit hit = scene.geometry().intersectFast(ray.position, ray.direction, 1e-7);
      const double leg = hit.hit ? hit.distance_m : std::numeric_limits<double>::infinity();
      if (tracking) {
        if (!(ray.specular_only && ray.order <= options.image_source_order)) {
          depositTrack(histogram, ray, std::min(leg, max_distance - ray.travelled), ray.bands & slice.active);
        }
      } else if (ray.last_specular && !(ray.specular_only && ray.order <= options.image_source_order)) {
        const Eigen::Vector3d to_listener = listener - ray.position;
        const double along = to_listener.dot(ray.direction);
        if (along > 0.0 && along < leg && (to_listener - along * ray.direction).squaredNorm() < r * r &&
            ray.travelled + along < max_distance) {
          deposit(histogram, ray.energy, ray.travelled + along, sphere_factor, -ray.direction, ray.bands & slice.active);
          note(slice, LedgerEvent::kSphere, 0, ray.travelled + along, sphere_factor, -ray.direction);
          ++stats.sphere_detections;
        }
      }
      const double leg_end = std::min(ray.travelled + leg, max_distance);
      if (slice.by_cell) addInFlightByCell(*slice.by_cell, ray, ray.travelled, leg_end);
      if (slice.fine) {
        addInFlight(*slice.fine, ray, ray.travelled, leg_end);
        if (!(ray.specular_only && ray.order <= options.image_source_order)) addInFlight(*slice.late, ray, ray.travelled, leg_end);
      }
      if (!hit.hit) {
        ++(scene.closed() ? stats.leaked_rays : stats.escaped_rays);
        if (slice.losses) {  // its energy has left the room
          OctaveBandValues& loss = lossAt(slice, ray.travelled);
          forEachBand(ray.bands, [&](int b) { loss[b] += ray.energy[b]; });
        }
        note(slice, LedgerEvent::kEnd);
        return;
      }
      if (ray.travelled + leg >= max_distance) {
        ++stats.stopped_by_time;
        for (int b = 0; b < kOctaveBandCount; ++b) {
          stats.energy_left_at_time_limit[b] += ray.energy[b] * std::exp(-model.air_attenuation_per_m[b] * max_distance);
        }
        note(slice, LedgerEvent::kEnd);
        return;
      }
      ray.travelled += leg;
      ray.position += leg * ray.direction;
      ++ray.order;
      ++stats.reflections;
      const MaterialTerms& m = terms[static_cast<std::size_t>(scene.mesh().triangle_material[hit.triangle])];
      const bool facing = hit.normal.dot(ray.direction) < 0.0;
      const Eigen::Vector3d normal = facing ? hit.normal : Eigen::Vector3d(-hit.normal);
      const double wall_offset = facing ? plane_offset[hit.triangle] : -plane_offset[hit.triangle];
      OctaveBandValues* loss = nullptr;
      if (slice.losses) {
        loss = &lossAt(slice, ray.travelled);
        forEachBand(ray.bands, [&](int b) { (*loss)[b] += ray.energy[b] * (1.0 - m.reflectance[b]); });
      }
      forEachBand(ray.bands, [&](int b) { ray.energy[b] *= m.reflectance[b]; });
      const OctaveBandValues scattering =
          options.diffraction_scattering
              ? withDiffractionScattering(m.scattering, scene.surfaceExtent(hit.triangle), ray.direction,
                                          characteristicDistance(leg, mean_free_path_m > 0.0 ? mean_free_path_m : leg),
                                          model.speed_of_sound_m_s, scene.bandCentresHz())
              : m.scattering;
      const RainArrival rained = options.diffuse_rain && !tracking
                                     ? rain(histogram, ray, hit.triangle, scattering, normal, ray.bands & slice.active)
                                     : RainArrival{};
      note(slice, LedgerEvent::kReflect, static_cast<std::uint32_t>(hit.triangle), rained.distance_m, rained.factor,
           rained.direction);
      // Back onto the wall's plane (the float hit distance leaves the point up to ~1e-6 m
      // either side of it), then just off it on the room's side.
      ray.position += (wall_offset - normal.dot(ray.position)) * normal + kSurfaceOffset_m * normal;
      double survivor_gain = 1.0;
      if (rouletteEnds(ray, loss, survivor_gain)) {
        ++stats.stopped_by_energy;
        note(slice, LedgerEvent::kEnd);
        return;
      }
      if (survivor_gain != 1.0) note(slice, LedgerEvent::kRoulette, 0, 0.0, survivor_gain);
      const double draw = keyedUniform(ray.key, ray.order, kScatter);
      BandMask diffuse = 0;
      forEachBand(ray.bands, [&](int b) {
        if (draw < scattering[b]) diffuse |= 1u << b;
      });
      const Eigen::Vector3d mirrored = ray.direction - 2.0 * ray.direction.dot(normal) * normal;
      if (diffuse != 0 && diffuse != ray.bands) {
        RayBranch specular = ray;
        specular.bands = ray.bands & ~diffuse;
        specular.direction = mirrored;
        // The diffuse part keeps the key, so it follows the path a model in which every band
        // scattered here would take; the specular part gets its own numbers.
        specular.key = mixBits(ray.key ^ (0x5eed5eedull + static_cast<std::uint64_t>(ray.order)));
        forEachBand(diffuse, [&](int b) { specular.energy[b] = 0.0; });
        forEachBand(specular.bands, [&](int b) { ray.energy[b] = 0.0; });
        if (specular.bands & slice.active) pending.push_back(specular);
        // Kept only while every band is traced: both parts are then always followed.
        note(slice, LedgerEvent::kSplit, diffuse);
        ray.bands = diffuse;
        if (!(ray.bands & slice.active)) {
          note(slice, LedgerEvent::kEnd);
          return;
        }
      }
      if (diffuse != 0) {
        ray.direction = lambertDirection(normal, keyedUniform(ray.key, ray.order, kLambertRadius),
                                         keyedUniform(ray.key, ray.order, kLambertAzimuth));
        ray.specular_only = false;
        ray.last_specular = false;
      } else {
        ray.direction = mirrored;
        ray.last_specular = true;
      }
    }
  }

  // What a reflection's diffuse rain delivered: the scattered energy times `factor`
  // after `distance_m` of travel, from `direction`; factor 0 when it delivered nothing.
  struct RainArrival {
    double distance_m = 0.0;
    double factor = 0.0;
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  };

  // Diffuse rain (Schröder 2011): the scattered share of this reflection sent straight to
  // the receiver when it sees the wall point (asking Embree only where no cell of the
  // triangle's visibility says so).
  RainArrival rain(EnergyHistogram& histogram, const RayBranch& ray, std::size_t triangle,
                   const OctaveBandValues& scattering, const Eigen::Vector3d& normal, BandMask bands) const {
    const Eigen::Vector3d to_listener = listener - ray.position;
    const double facing = normal.dot(to_listener);
    if (!(facing > 0.0)) return {};  // the listener is behind the wall: no root or division
    const double d = to_listener.norm();
    const double cos_theta = facing / d;
    OctaveBandValues scattered;
    bool any = false;
    forEachBand(bands, [&](int b) {
      scattered[b] = ray.energy[b] * scattering[b];
      any = any || scattered[b] > 0.0;
    });
    if (!any || (!visibility.sees(triangle, ray.position) && scene.geometry().occluded(ray.position, listener, 1e-5))) return {};
    const RainArrival arrival{ray.travelled + d, cos_theta / (kPi * d * d), -to_listener / d};
    deposit(histogram, scattered, arrival.distance_m, arrival.factor, arrival.direction, bands);
    return arrival;
  }
};

// A thread's share: its energies are shares of the same emission, so they add.
void addStats(RayTracingStats& total, const RayTracingStats& part) {
  addRayCounts(total, part);
  for (int b = 0; b < kOctaveBandCount; ++b) total.energy_left_at_time_limit[b] += part.energy_left_at_time_limit[b];
}

}  // namespace

void addRayCounts(RayTracingStats& total, const RayTracingStats& part) {
  total.rays += part.rays;
  total.reflections += part.reflections;
  total.leaked_rays += part.leaked_rays;
  total.escaped_rays += part.escaped_rays;
  total.stopped_by_time += part.stopped_by_time;
  total.stopped_by_energy += part.stopped_by_energy;
  total.sphere_detections += part.sphere_detections;
}

double autoReceiverRadius(const AcousticScene& scene, const Eigen::Vector3d& listener, std::size_t ray_count,
                          double speed_of_sound_m_s, double crossings_per_ms) {
  const double volume_m3 = scene.volumeM3() > 0.0 ? scene.volumeM3() : 1.0;
  const double rays = static_cast<double>(std::max<std::size_t>(ray_count, 1));
  const double wanted = std::sqrt(crossings_per_ms * volume_m3 / (rays * kPi * speed_of_sound_m_s * 1e-3));
  const double clearance = 0.9 * scene.distanceToNearestSurface(listener);
  return std::max(std::min({wanted, 1.5, clearance}), std::min(0.1, clearance));
}

RayTracingResult traceRays(const AcousticScene& scene, const Eigen::Vector3d& source,
                           const Eigen::Vector3d& listener, const PropagationModel& model,
                           const RayTracingOptions& options, std::size_t ledger_budget_bytes) {
  if (options.ray_count == 0) throw InputError("the ray count must be at least 1");
  if (!(options.roulette_db <= 0.0)) throw InputError("the Russian roulette level must be 0 dB or below");
  if (!(options.max_time_s > 0.0) || !(options.bin_s > 0.0)) throw InputError("ray tracing needs a positive duration and bin width");
  if (!(options.receiver_radius_m >= 0.0)) throw InputError("the receiver radius must be positive (or 0: automatic)");
  if (!(options.crossings_per_ms > 0.0)) throw InputError("the detection sphere's crossings per millisecond must be positive");
  if (!(options.track_radius_m >= 0.0) || !std::isfinite(options.track_radius_m)) {
    throw InputError("the track receiver's radius must be 0 (none) or a positive number of metres");
  }
  const int threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const auto bins = static_cast<std::size_t>(std::ceil(options.max_time_s / options.bin_s));
  const double radius = options.receiver_radius_m > 0.0
                            ? options.receiver_radius_m
                            : autoReceiverRadius(scene, listener, options.ray_count, model.speed_of_sound_m_s,
                                                 options.crossings_per_ms);
  const Tracer tracer(scene, source, listener, model, options, radius, 1.0 / static_cast<double>(options.ray_count), bins);
  const std::size_t chunks = (options.ray_count + kRaysPerChunk - 1) / kRaysPerChunk;

  std::vector<EnergyHistogram> histograms(static_cast<std::size_t>(threads), EnergyHistogram(options.bin_s, bins));
  std::vector<RayTracingStats> stats(static_cast<std::size_t>(threads));
  std::vector<std::vector<OctaveBandValues>> in_flight(
      options.record_energy_in_flight ? static_cast<std::size_t>(threads) : 0, std::vector<OctaveBandValues>(bins, OctaveBandValues{}));
  std::vector<std::vector<OctaveBandValues>> late_in_flight = in_flight;
  const std::size_t cell_bins = tracer.cell_air.size() / kOctaveBandCount;  // 0 unless record_launch_cells
  std::vector<std::vector<OctaveBandValues>> by_cell(options.record_launch_cells ? static_cast<std::size_t>(threads) : 0,
                                                     std::vector<OctaveBandValues>(kLaunchCells * cell_bins, OctaveBandValues{}));
  const bool continuing = options.continue_established_decays;
  const std::size_t flight_bins = Tracer::flightBins(options.max_time_s);
  std::vector<std::vector<OctaveBandValues>> losses(continuing ? static_cast<std::size_t>(threads) : 0,
                                                    std::vector<OctaveBandValues>(flight_bins, OctaveBandValues{}));
  std::vector<std::vector<RayBranch>> parked(chunks);
  // The paths, per chunk, while they fit the budget (path_ledger.h).
  // (Replay knows the detection sphere's crossings only.)
  const bool keeping = ledger_budget_bytes > 0 && !options.diffraction_scattering && !(options.track_radius_m > 0.0);
  std::vector<std::vector<LedgerEvent>> ledger_chunks(keeping ? chunks : 0);
  std::atomic<std::size_t> ledger_bytes{0};
  std::atomic<bool> ledger_overflow{false};
  BandMask active = kAllBands;
  std::array<std::optional<EstablishedDecay>, kOctaveBandCount> lines;
  OctaveBandValues traced_until;
  traced_until.fill(options.max_time_s);

  double next_end_s = kSliceS;
  for (int slice_index = 0;; ++slice_index) {
    const double end_s = continuing ? std::min(next_end_s, options.max_time_s) : options.max_time_s;
    const bool last = end_s >= options.max_time_s - 1e-12;
    auto work = [&](int thread) {
      const auto t = static_cast<std::size_t>(thread);
      std::vector<RayBranch> pending, resumed;
      Slice slice;
      slice.boundary_m = last ? std::numeric_limits<double>::infinity() : end_s * model.speed_of_sound_m_s;
      slice.active = active;
      slice.fine = in_flight.empty() ? nullptr : &in_flight[t];
      slice.late = late_in_flight.empty() ? nullptr : &late_in_flight[t];
      slice.by_cell = by_cell.empty() ? nullptr : &by_cell[t];
      slice.losses = losses.empty() ? nullptr : &losses[t];
      for (std::size_t chunk = t; chunk < chunks; chunk += static_cast<std::size_t>(threads)) {
        slice.parked = &parked[chunk];
        slice.ledger = keeping && !ledger_overflow.load(std::memory_order_relaxed) ? &ledger_chunks[chunk] : nullptr;
        const std::size_t ledger_before = slice.ledger ? slice.ledger->size() : 0;
        if (slice_index == 0) {
          const std::size_t end = std::min(options.ray_count, (chunk + 1) * kRaysPerChunk);
          for (std::size_t ray = chunk * kRaysPerChunk; ray < end; ++ray) tracer.traceRay(ray, pending, histograms[t], stats[t], slice);
        } else {
          resumed.clear();
          resumed.swap(parked[chunk]);
          note(slice, LedgerEvent::kSlice);
          for (RayBranch& branch : resumed) {
            if (!(branch.bands & active)) continue;
            note(slice, LedgerEvent::kResume);
            tracer.traceBranch(branch, pending, histograms[t], stats[t], slice);
            tracer.tracePending(pending, histograms[t], stats[t], slice);
          }
        }
        if (slice.ledger) {
          const std::size_t added = (slice.ledger->size() - ledger_before) * sizeof(LedgerEvent);
          if (ledger_bytes.fetch_add(added) + added > ledger_budget_bytes) ledger_overflow = true;
        }
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
    work(0);
    for (auto& thread : pool) thread.join();
    if (last) break;
    // Which bands the slices so far establish (every flight bin before end_s is complete).
    const auto complete = static_cast<std::size_t>(std::floor(end_s / kFlightBinS + 1e-9));
    std::vector<double> band_energy(flight_bins);
    bool judged = false;  // a traced band has fallen far enough to be judged, and bends
    double soonest_s = std::numeric_limits<double>::infinity();  // until the next one has
    for (int b = 0; b < kOctaveBandCount; ++b) {
      if (!(active >> b & 1u)) continue;
      // The energy in flight without air is what the launches gave less what the walls and
      // the roulette took before each bin's end; every ray has travelled the same distance
      // at one time, so the air's loss is one factor for all. Each bin gets the geometric
      // mean of its two ends, close to its value at its centre.
      double left = 0.0, at_start = 0.0;
      for (std::size_t k = 0; k < flight_bins; ++k) {
        for (const auto& part : losses) left -= part[k][b];
        const double at_end = left;
        band_energy[k] = (k == 0 ? at_end : std::sqrt(std::max(0.0, at_start * at_end))) *
                         std::exp(-model.air_attenuation_per_m[b] * (static_cast<double>(k) + 0.5) * kFlightBinS *
                                  model.speed_of_sound_m_s);
        at_start = at_end;
      }
      lines[b] = establishedDecay(band_energy, complete, kFlightBinS, options.continuation);
      if (lines[b]) {
        active &= ~(1u << b);
        traced_until[b] = end_s;
        continue;
      }
      const double fallen_db = 10.0 * std::log10(band_energy[0] / band_energy[complete - 1]);
      if (!(fallen_db < options.continuation.decayed_db)) {
        judged = true;
        continue;
      }
      const std::size_t recent = std::min<std::size_t>(complete - 1, 5);
      const double falling_db_per_s =
          10.0 * std::log10(band_energy[complete - 1 - recent] / band_energy[complete - 1]) / (static_cast<double>(recent) * kFlightBinS);
      if (falling_db_per_s > 0.0) soonest_s = std::min(soonest_s, (options.continuation.decayed_db - fallen_db) / falling_db_per_s);
    }
    const bool waiting = std::any_of(parked.begin(), parked.end(), [](const auto& p) { return !p.empty(); });
    if (active == 0 || !waiting) break;
    // A slice ends where the judgement may change: when the first traced band will have
    // fallen far enough (its fall over the last 25 ms carried on), so that each band stops
    // within a slice of its own 25 dB; while a band that has fallen that far still bends,
    // after a quarter of the time so far. Each slice parks and resumes every live branch,
    // a copy of each: on BRAS CR2 ten slices trace 10 % fewer reflections than eight
    // slices a quarter of the time apart (bands stopped 0.02-0.19 s after their 25 dB).
    double wait_s = judged ? 0.25 * end_s : std::numeric_limits<double>::infinity();
    wait_s = std::min(wait_s, soonest_s);
    if (!std::isfinite(wait_s)) wait_s = 0.25 * end_s;
    wait_s = std::max(kSliceS, wait_s);
    next_end_s = kFlightBinS * std::ceil((end_s + wait_s) / kFlightBinS - 1e-9);
  }

  RayTracingResult result{EnergyHistogram(options.bin_s, bins), {}, {}, {}, {}, nullptr};
  for (int t = 0; t < threads; ++t) result.histogram.merge(histograms[static_cast<std::size_t>(t)]);
  for (int t = 0; t < threads; ++t) addStats(result.stats, stats[t]);
  result.stats.receiver_radius_m = options.track_radius_m > 0.0 ? options.track_radius_m : radius;
  result.stats.traced_until_s = traced_until;
  // A continued band's later arrivals were never deposited, so its paths say nothing of
  // its tail: no ledger then.
  if (keeping && !ledger_overflow && active == kAllBands) {
    auto ledger = std::make_shared<PathLedger>();
    ledger->chunks = std::move(ledger_chunks);
    ledger->rays_per_chunk = kRaysPerChunk;
    ledger->threads = threads;
    ledger->source = source;
    ledger->listener = listener;
    ledger->seed = options.seed;
    ledger->ray_count = options.ray_count;
    ledger->ray_energy = tracer.ray_energy;
    ledger->bin_s = options.bin_s;
    ledger->bins = bins;
    ledger->speed_of_sound_m_s = model.speed_of_sound_m_s;
    ledger->directivity = model.directivity;
    ledger->mesh_fingerprint = meshFingerprint(scene.mesh());
    for (std::size_t t = 0; t < scene.mesh().triangleCount(); ++t) {
      const MaterialTerms& m = tracer.terms[static_cast<std::size_t>(scene.mesh().triangle_material[t])];
      ledger->reflectance.push_back(m.reflectance);
      ledger->scattering.push_back(m.scattering);
    }
    ledger->image_source_order = options.image_source_order;
    decayRange(result.histogram, model.speed_of_sound_m_s, ledger->decay_from_m, ledger->decay_to_m);
    result.ledger = std::move(ledger);
  }
  const auto sum_parts = [&](const std::vector<std::vector<OctaveBandValues>>& parts, std::vector<OctaveBandValues>& out) {
    if (parts.empty()) return;
    out.assign(parts.front().size(), OctaveBandValues{});
    for (const auto& part : parts) {
      for (std::size_t k = 0; k < out.size(); ++k) {
        for (int b = 0; b < kOctaveBandCount; ++b) out[k][b] += part[k][b];
      }
    }
  };
  sum_parts(in_flight, result.energy_in_flight);
  sum_parts(late_in_flight, result.late_energy_in_flight);
  sum_parts(by_cell, result.energy_in_flight_by_launch_cell);
  for (int b = 0; b < kOctaveBandCount; ++b) {
    if (!lines[b]) continue;
    const EstablishedDecay& line = *lines[b];
    continueDecay(result.histogram, b, line.fitted_from_s, traced_until[b], line);
    result.stats.energy_left_at_time_limit[b] = line.energyAt(options.max_time_s);
    const auto from_bin = static_cast<std::size_t>(std::floor(traced_until[b] / options.bin_s + 1e-9));
    for (std::size_t k = from_bin; k < result.energy_in_flight.size(); ++k) {
      result.energy_in_flight[k][b] = line.energyAt((static_cast<double>(k) + 0.5) * options.bin_s);
      result.late_energy_in_flight[k][b] = result.energy_in_flight[k][b];
    }
  }
  return result;
}

}  // namespace room_reverb::core
