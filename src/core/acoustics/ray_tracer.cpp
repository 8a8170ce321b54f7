#include "room_reverb/acoustics/ray_tracer.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Rays are traced in fixed chunks with their own generator, and chunk c always goes to
// thread c mod T: the same seed and thread count give the same sums in the same order.
constexpr std::size_t kRaysPerChunk = 256;
// A new leg starts this far off the wall, after the point is put back onto its plane.
constexpr double kSurfaceOffset_m = 1e-6;

Eigen::Vector3d uniformDirection(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = 2.0 * u(rng) - 1.0;
  const double phi = 2.0 * kPi * u(rng);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Lambert (cosine-weighted) direction about the unit normal n.
Eigen::Vector3d lambertDirection(const Eigen::Vector3d& n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double r = std::sqrt(u(rng));
  const double phi = 2.0 * kPi * u(rng);
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d t1 = n.cross(helper).normalized();
  const Eigen::Vector3d t2 = n.cross(t1);
  return (r * std::cos(phi) * t1 + r * std::sin(phi) * t2 + std::sqrt(std::max(0.0, 1.0 - r * r)) * n).normalized();
}

// Per-material factors of one reflection, worked out once per traceRays call instead of
// at every hit (same arithmetic as before, so the same numbers).
struct MaterialTerms {
  OctaveBandValues reflectance{};      // 1 - absorption
  OctaveBandValues scattering{};
  OctaveBandValues diffuse_weight{};   // s / p
  OctaveBandValues specular_weight{};  // (1 - s) / (1 - p)
  double mean_scattering = 0.0;        // p
};

struct Tracer {
  const AcousticScene& scene;
  const Eigen::Vector3d& source;
  const Eigen::Vector3d& listener;
  const PropagationModel& model;
  const RayTracingOptions& options;
  double ray_energy;
  std::vector<MaterialTerms> terms;       // per scene material
  std::vector<double> plane_offset;       // per triangle: normal . vertex0
  std::vector<double> air_upper, air_lower;  // [k][band]: exp(-m k L), exp(-m (k+1) L), L = c bin_s
  double bin_length_m;
  double floor;

  Tracer(const AcousticScene& scene_, const Eigen::Vector3d& source_, const Eigen::Vector3d& listener_,
         const PropagationModel& model_, const RayTracingOptions& options_, double ray_energy_, std::size_t bins)
      : scene(scene_), source(source_), listener(listener_), model(model_), options(options_), ray_energy(ray_energy_) {
    for (const AcousticMaterial& material : scene.materials()) {
      MaterialTerms t;
      for (int b = 0; b < kOctaveBandCount; ++b) {
        t.reflectance[b] = 1.0 - material.absorption[b];
        t.scattering[b] = material.scattering[b];
        t.mean_scattering += material.scattering[b] / kOctaveBandCount;
      }
      for (int b = 0; b < kOctaveBandCount; ++b) {
        t.diffuse_weight[b] = t.mean_scattering > 0.0 ? material.scattering[b] / t.mean_scattering : 0.0;
        t.specular_weight[b] = t.mean_scattering < 1.0 ? (1.0 - material.scattering[b]) / (1.0 - t.mean_scattering) : 0.0;
      }
      terms.push_back(t);
    }
    const TriangleMesh& mesh = scene.mesh();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) plane_offset.push_back(mesh.normal(t).dot(mesh.vertices[mesh.triangles[t][0]]));
    bin_length_m = options.bin_s * model.speed_of_sound_m_s;
    air_upper.resize((bins + 2) * kOctaveBandCount);
    air_lower.resize((bins + 2) * kOctaveBandCount);
    for (std::size_t k = 0; k < bins + 2; ++k) {
      for (int b = 0; b < kOctaveBandCount; ++b) {
        air_upper[k * kOctaveBandCount + b] = std::exp(-model.air_attenuation_per_m[b] * (static_cast<double>(k) * bin_length_m));
        air_lower[k * kOctaveBandCount + b] = std::exp(-model.air_attenuation_per_m[b] * (static_cast<double>(k + 1) * bin_length_m));
      }
    }
    floor = ray_energy * std::pow(10.0, options.energy_floor_db / 10.0);
  }

  // Arrival of `energy` after `distance_m` scaled by `factor`, with air: exp(-m d) as the
  // table's exp(-m k L) times a 5-term series of exp(-x), x = m (d - k L) <= m L (1e-9 exact).
  void deposit(EnergyHistogram& histogram, const OctaveBandValues& energy, double distance_m, double factor,
               const Eigen::Vector3d& direction) const {
    const std::size_t k = std::min(static_cast<std::size_t>(std::max(0.0, distance_m) / bin_length_m), air_upper.size() / kOctaveBandCount - 2);
    const double* upper = &air_upper[k * kOctaveBandCount];
    const double rest = distance_m - static_cast<double>(k) * bin_length_m;
    OctaveBandValues weight;
    for (int b = 0; b < kOctaveBandCount; ++b) {
      const double x = model.air_attenuation_per_m[b] * rest;
      const double series = 1.0 - x * (1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0))));
      weight[b] = factor * upper[b] * series;
    }
    histogram.addBands(distance_m / model.speed_of_sound_m_s, energy, weight, direction);
  }

  // max over bands of energy * exp(-m travelled) < floor, decided from the tables when
  // they settle it (they bound the exact factor from both sides), exactly otherwise.
  bool belowFloor(const OctaveBandValues& energy, double travelled) const {
    const std::size_t k = std::min(static_cast<std::size_t>(travelled / bin_length_m), air_upper.size() / kOctaveBandCount - 2);
    const double* upper = &air_upper[k * kOctaveBandCount];
    const double* lower = &air_lower[k * kOctaveBandCount];
    double hi = 0.0, lo = 0.0;
    for (int b = 0; b < kOctaveBandCount; ++b) {
      hi = std::max(hi, energy[b] * upper[b]);
      lo = std::max(lo, energy[b] * lower[b]);
    }
    if (hi < floor) return true;
    if (lo >= floor) return false;
    double loudest = 0.0;
    for (int b = 0; b < kOctaveBandCount; ++b) {
      loudest = std::max(loudest, energy[b] * std::exp(-model.air_attenuation_per_m[b] * travelled));
    }
    return loudest < floor;
  }

  void traceRay(std::mt19937_64& rng, EnergyHistogram& histogram, RayTracingStats& stats) const {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Eigen::Vector3d direction = uniformDirection(rng);
    const double gain = model.directivity.pressureGain(direction);
    OctaveBandValues energy;
    energy.fill(ray_energy * gain * gain);
    const double max_distance = options.max_time_s * model.speed_of_sound_m_s;
    const double r = options.receiver_radius_m;
    const double sphere_factor = 1.0 / (kPi * r * r);
    Eigen::Vector3d position = source;
    double travelled = 0.0;
    int order = 0;
    bool specular_only = true;
    bool last_specular = true;
    ++stats.rays;
    for (;;) {
      const RayHit hit = scene.geometry().intersect(position, direction, 1e-7);
      const double leg = hit.hit ? hit.distance_m : std::numeric_limits<double>::infinity();
      if (last_specular && !(specular_only && order <= options.image_source_order)) {
        const Eigen::Vector3d to_listener = listener - position;
        const double along = to_listener.dot(direction);
        if (along > 0.0 && along < leg && (to_listener - along * direction).squaredNorm() < r * r &&
            travelled + along < max_distance) {
          deposit(histogram, energy, travelled + along, sphere_factor, -direction);
          ++stats.sphere_detections;
        }
      }
      if (!hit.hit) {
        ++(scene.closed() ? stats.leaked_rays : stats.escaped_rays);
        return;
      }
      if (travelled + leg >= max_distance) {
        ++stats.stopped_by_time;
        for (int b = 0; b < kOctaveBandCount; ++b) {
          stats.energy_left_at_time_limit[b] += energy[b] * std::exp(-model.air_attenuation_per_m[b] * max_distance);
        }
        return;
      }
      travelled += leg;
      position += leg * direction;
      ++order;
      ++stats.reflections;
      const MaterialTerms& m = terms[static_cast<std::size_t>(scene.mesh().triangle_material[hit.triangle])];
      const bool facing = hit.normal.dot(direction) < 0.0;
      const Eigen::Vector3d normal = facing ? hit.normal : Eigen::Vector3d(-hit.normal);
      auto wall_offset = [&](std::size_t t) { return facing ? plane_offset[t] : -plane_offset[t]; };
      for (int b = 0; b < kOctaveBandCount; ++b) energy[b] *= m.reflectance[b];
      if (options.diffuse_rain && m.mean_scattering > 0.0) {
        const Eigen::Vector3d to_listener = listener - position;
        const double d = to_listener.norm();
        const double cos_theta = normal.dot(to_listener) / d;
        if (cos_theta > 0.0 && !scene.geometry().occluded(position, listener, 1e-5)) {
          OctaveBandValues scattered;
          for (int b = 0; b < kOctaveBandCount; ++b) scattered[b] = energy[b] * m.scattering[b];
          deposit(histogram, scattered, travelled + d, cos_theta / (kPi * d * d), -to_listener / d);
        }
      }
      if (u(rng) < m.mean_scattering) {
        for (int b = 0; b < kOctaveBandCount; ++b) energy[b] *= m.diffuse_weight[b];
        direction = lambertDirection(normal, rng);
        specular_only = false;
        last_specular = false;
      } else {
        for (int b = 0; b < kOctaveBandCount; ++b) energy[b] *= m.specular_weight[b];
        direction = direction - 2.0 * direction.dot(normal) * normal;
        last_specular = true;
      }
      // Back onto the wall's plane (the float hit distance leaves the point up to ~1e-6 m
      // either side of it), then just off it on the room's side.
      position += (wall_offset(hit.triangle) - normal.dot(position)) * normal + kSurfaceOffset_m * normal;
      if (belowFloor(energy, travelled)) {
        ++stats.stopped_by_energy;
        return;
      }
    }
  }
};

void addStats(RayTracingStats& total, const RayTracingStats& part) {
  total.rays += part.rays;
  total.reflections += part.reflections;
  total.leaked_rays += part.leaked_rays;
  total.escaped_rays += part.escaped_rays;
  total.stopped_by_time += part.stopped_by_time;
  total.stopped_by_energy += part.stopped_by_energy;
  total.sphere_detections += part.sphere_detections;
  for (int b = 0; b < kOctaveBandCount; ++b) total.energy_left_at_time_limit[b] += part.energy_left_at_time_limit[b];
}

}  // namespace

RayTracingResult traceRays(const AcousticScene& scene, const Eigen::Vector3d& source,
                           const Eigen::Vector3d& listener, const PropagationModel& model,
                           const RayTracingOptions& options) {
  if (options.ray_count == 0) throw InputError("the ray count must be at least 1");
  if (!(options.max_time_s > 0.0) || !(options.bin_s > 0.0)) throw InputError("ray tracing needs a positive duration and bin width");
  if (!(options.receiver_radius_m > 0.0)) throw InputError("the receiver radius must be positive");
  const int threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const auto bins = static_cast<std::size_t>(std::ceil(options.max_time_s / options.bin_s));
  const Tracer tracer(scene, source, listener, model, options, 1.0 / static_cast<double>(options.ray_count), bins);
  const std::size_t chunks = (options.ray_count + kRaysPerChunk - 1) / kRaysPerChunk;

  std::vector<EnergyHistogram> histograms(static_cast<std::size_t>(threads), EnergyHistogram(options.bin_s, bins));
  std::vector<RayTracingStats> stats(static_cast<std::size_t>(threads));
  auto work = [&](int thread) {
    for (std::size_t chunk = static_cast<std::size_t>(thread); chunk < chunks; chunk += static_cast<std::size_t>(threads)) {
      std::seed_seq seq{options.seed, static_cast<std::uint32_t>(chunk), static_cast<std::uint32_t>(chunk >> 32)};
      std::mt19937_64 rng(seq);
      const std::size_t end = std::min(options.ray_count, (chunk + 1) * kRaysPerChunk);
      for (std::size_t ray = chunk * kRaysPerChunk; ray < end; ++ray) tracer.traceRay(rng, histograms[thread], stats[thread]);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& thread : pool) thread.join();

  RayTracingResult result{EnergyHistogram(options.bin_s, bins), {}};
  for (int t = 0; t < threads; ++t) result.histogram.merge(histograms[static_cast<std::size_t>(t)]);
  for (int t = 0; t < threads; ++t) addStats(result.stats, stats[t]);
  return result;
}

}  // namespace room_reverb::core
