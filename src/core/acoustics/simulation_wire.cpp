#include "room_reverb/acoustics/simulation_wire.h"

#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "room_reverb/common/byte_stream.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

// Magic numbers with the encoding's version in the low byte; read back in another byte
// order they do not match, so a foreign machine's bytes are refused, not misread.
constexpr std::uint32_t kSceneMarker = 0x52525303;    // "RRS" 3
constexpr std::uint32_t kRequestMarker = 0x52525107;  // "RRQ" 7
constexpr std::uint32_t kResultMarker = 0x52525202;   // "RRR" 2
constexpr std::uint32_t kJobMarker = 0x52524a01;      // "RRJ" 1

// Each struct below is written field by field. Its size is checked so that a field added
// to it fails this build until the encoding carries it too (x86-64 and AArch64 layouts).
static_assert(sizeof(AirConditions) == 32, "AirConditions changed: encode the new field");
static_assert(sizeof(SourceDirectivity) == 32, "SourceDirectivity changed: encode the new field");
static_assert(sizeof(DecayContinuationOptions) == 40, "DecayContinuationOptions changed: encode the new field");
static_assert(sizeof(RayTracingOptions) == 136, "RayTracingOptions changed: encode the new field");
static_assert(sizeof(SimulationSettings) == 320, "SimulationSettings changed: encode the new field");
static_assert(sizeof(FastRayOptions) == 48, "FastRayOptions changed: encode the new field");
static_assert(sizeof(WaveLowBandOptions) == 24, "WaveLowBandOptions changed: encode the new field");  // bands fills the padding
static_assert(sizeof(WaveLowBandStats) == 56, "WaveLowBandStats changed: encode the new field");
static_assert(sizeof(RayTracingStats) == 208, "RayTracingStats changed: encode the new field");
static_assert(sizeof(SpecularPath) == 168, "SpecularPath changed: encode the new field");
static_assert(sizeof(CuboidObject) == 240, "CuboidObject changed: encode the new field");
static_assert(sizeof(AcousticMaterial) == 656, "AcousticMaterial changed: encode the new field");

void putVector(ByteWriter& w, const Eigen::Vector3d& v) {
  for (int k = 0; k < 3; ++k) w.put<double>(v[k]);
}
Eigen::Vector3d getVector(ByteReader& r) {
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) v[k] = r.get<double>();
  return v;
}
void putBands(ByteWriter& w, const OctaveBandValues& values) {
  for (double v : values) w.put<double>(v);
}
OctaveBandValues getBands(ByteReader& r) {
  OctaveBandValues values{};
  for (double& v : values) v = r.get<double>();
  return values;
}

void putSettings(ByteWriter& w, const SimulationSettings& s) {
  w.put<std::int32_t>(static_cast<std::int32_t>(s.mode));
  w.put<std::int32_t>(s.image_source_order);
  w.put<double>(s.duration_s);
  w.put<std::int32_t>(s.ambisonic_order);
  w.putBool(s.air.enabled);
  w.put<double>(s.air.temperature_c);
  w.put<double>(s.air.humidity_percent);
  w.put<double>(s.air.pressure_kpa);
  w.put<double>(s.directivity.omni_fraction);
  putVector(w, s.directivity.axis);
  const RayTracingOptions& o = s.rays;
  w.put<std::uint64_t>(o.ray_count);
  w.put<double>(o.max_time_s);
  w.put<double>(o.bin_s);
  w.put<double>(o.receiver_radius_m);
  w.put<double>(o.crossings_per_ms);
  w.put<double>(o.track_radius_m);
  w.put<double>(o.roulette_db);
  w.put<std::int32_t>(o.image_source_order);
  w.putBool(o.diffuse_rain);
  w.putBool(o.diffraction_scattering);
  w.putBool(o.record_energy_in_flight);
  w.putBool(o.continue_established_decays);
  w.putBool(o.record_launch_cells);
  w.putBool(o.launch_density != nullptr);
  if (o.launch_density) {
    for (double p : o.launch_density->probabilities()) w.put<double>(p);
  }
  w.put<double>(o.continuation.decayed_db);
  w.put<double>(o.continuation.straight_span_db);
  w.put<double>(o.continuation.bend_horizon_db);
  w.put<double>(o.continuation.bend_db);
  w.put<double>(o.continuation.scatter_db);
  w.put<std::uint32_t>(o.seed);
  w.put<std::int32_t>(o.threads);
  w.put<std::uint64_t>(s.fast_ray_count);
  w.put<double>(s.fast_rays.rate_tolerance);
  w.put<std::uint64_t>(s.fast_rays.min_rays);
  w.put<std::uint64_t>(s.fast_rays.batch_rays);
  w.put<double>(s.fast_rays.reflection_budget);
  w.put<double>(s.fast_rays.track_radius_m);
  w.put<double>(s.fast_rays.late_launch_mixture);
  w.putBool(s.diffraction_scattering);
  w.put<std::int32_t>(static_cast<std::int32_t>(s.low_band));
  w.put<double>(s.wave.crossover_hz);
  w.put<double>(s.wave.cells_per_wavelength);
  w.put<std::int32_t>(s.wave.threads);
  w.put<std::int32_t>(static_cast<std::int32_t>(s.wave.bands));
  w.put<std::int32_t>(static_cast<std::int32_t>(s.bands));
}

BandResolution getBandResolution(ByteReader& r) {
  const auto bands = r.get<std::int32_t>();
  if (bands < 0 || bands > static_cast<std::int32_t>(BandResolution::kThirdOctave)) r.fail("unknown band resolution " + std::to_string(bands));
  return static_cast<BandResolution>(bands);
}

SimulationSettings getSettings(ByteReader& r) {
  SimulationSettings s;
  const auto mode = r.get<std::int32_t>();
  if (mode < 0 || mode > static_cast<std::int32_t>(SimulationMode::kEyring)) r.fail("unknown simulation mode " + std::to_string(mode));
  s.mode = static_cast<SimulationMode>(mode);
  s.image_source_order = r.get<std::int32_t>();
  s.duration_s = r.get<double>();
  s.ambisonic_order = r.get<std::int32_t>();
  s.air.enabled = r.getBool();
  s.air.temperature_c = r.get<double>();
  s.air.humidity_percent = r.get<double>();
  s.air.pressure_kpa = r.get<double>();
  s.directivity.omni_fraction = r.get<double>();
  s.directivity.axis = getVector(r);
  RayTracingOptions& o = s.rays;
  o.ray_count = static_cast<std::size_t>(r.get<std::uint64_t>());
  o.max_time_s = r.get<double>();
  o.bin_s = r.get<double>();
  o.receiver_radius_m = r.get<double>();
  o.crossings_per_ms = r.get<double>();
  o.track_radius_m = r.get<double>();
  o.roulette_db = r.get<double>();
  o.image_source_order = r.get<std::int32_t>();
  o.diffuse_rain = r.getBool();
  o.diffraction_scattering = r.getBool();
  o.record_energy_in_flight = r.getBool();
  o.continue_established_decays = r.getBool();
  o.record_launch_cells = r.getBool();
  if (r.getBool()) {
    std::array<double, kLaunchCells> probabilities{};
    for (double& p : probabilities) p = r.get<double>();
    try {
      o.launch_density = std::make_shared<LaunchDensity>(LaunchDensity::fromProbabilities(probabilities));
    } catch (const InputError& e) {
      r.fail(e.what());
    }
  }
  o.continuation.decayed_db = r.get<double>();
  o.continuation.straight_span_db = r.get<double>();
  o.continuation.bend_horizon_db = r.get<double>();
  o.continuation.bend_db = r.get<double>();
  o.continuation.scatter_db = r.get<double>();
  o.seed = r.get<std::uint32_t>();
  o.threads = r.get<std::int32_t>();
  s.fast_ray_count = static_cast<std::size_t>(r.get<std::uint64_t>());
  s.fast_rays.rate_tolerance = r.get<double>();
  s.fast_rays.min_rays = static_cast<std::size_t>(r.get<std::uint64_t>());
  s.fast_rays.batch_rays = static_cast<std::size_t>(r.get<std::uint64_t>());
  s.fast_rays.reflection_budget = r.get<double>();
  s.fast_rays.track_radius_m = r.get<double>();
  s.fast_rays.late_launch_mixture = r.get<double>();
  s.diffraction_scattering = r.getBool();
  const auto low_band = r.get<std::int32_t>();
  if (low_band < 0 || low_band > static_cast<std::int32_t>(LowBandMethod::kWave)) r.fail("unknown low-band method " + std::to_string(low_band));
  s.low_band = static_cast<LowBandMethod>(low_band);
  s.wave.crossover_hz = r.get<double>();
  s.wave.cells_per_wavelength = r.get<double>();
  s.wave.threads = r.get<std::int32_t>();
  s.wave.bands = getBandResolution(r);
  s.bands = getBandResolution(r);
  return s;
}

void putRequest(ByteWriter& w, const SimulationRequest& request) {
  w.put<std::uint32_t>(kRequestMarker);
  putVector(w, request.source_m);
  putVector(w, request.listener_m);
  putSettings(w, request.settings);
}

SimulationRequest getRequest(ByteReader& r) {
  r.requireMarker(kRequestMarker);
  SimulationRequest request;
  request.source_m = getVector(r);
  request.listener_m = getVector(r);
  request.settings = getSettings(r);
  const RayTracingOptions& o = request.settings.rays;
  if (o.threads <= 0 || o.threads > 1024) r.fail("the request's thread count must be fixed (1 to 1024)");
  // What simulateRoom does not check itself, because its callers build these values.
  if (!(o.bin_s >= 1e-5 && o.bin_s <= 0.1)) r.fail("the histogram's bin width must be 10 us to 100 ms");
  return request;
}

}  // namespace

std::vector<std::uint8_t> encodeScene(const AcousticScene& scene) {
  ByteWriter w;
  w.put<std::uint32_t>(kSceneMarker);
  const TriangleMesh& mesh = scene.mesh();
  w.put<std::uint64_t>(mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices) putVector(w, v);
  w.put<std::uint64_t>(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) w.put<std::int32_t>(t[k]);
  }
  w.putArray(mesh.triangle_material.data(), mesh.triangle_material.size());
  // The materials as the scene resolved them (library entry, aliases and overrides
  // applied), one per name of the mesh.
  w.put<std::uint64_t>(mesh.material_names.size());
  for (std::size_t m = 0; m < mesh.material_names.size(); ++m) {
    const AcousticMaterial& material = scene.materials()[m];
    w.putString(mesh.material_names[m]);
    putBands(w, material.absorption);
    putBands(w, material.scattering);
    for (const std::optional<ThirdOctaveValues>* thirds : {&material.absorption_thirds, &material.scattering_thirds}) {
      w.putBool(thirds->has_value());
      if (*thirds) {
        for (const OctaveBandValues& third : **thirds) putBands(w, third);
      }
    }
    w.putString(material.source);
  }
  w.putBool(scene.closed());
  const RoomShape* shape = scene.roomShape();
  w.putBool(shape != nullptr);
  if (shape) {
    putVector(w, shape->size_m);
    w.putBool(shape->has_ceiling);
    w.put<std::uint64_t>(shape->objects.size());
    for (const CuboidObject& o : shape->objects) {
      w.putString(o.label);
      w.putString(o.material);
      putVector(w, o.center_m);
      putVector(w, o.size_m);
      w.put<double>(o.yaw_rad);
      w.put<double>(o.confidence);
      w.putString(o.runner_up);
      w.put<double>(o.runner_up_confidence);
      putBands(w, o.relief_scattering);
    }
  }
  return w.take();
}

std::unique_ptr<AcousticScene> decodeScene(const std::uint8_t* data, std::size_t size) {
  ByteReader r(data, size, "simulation scene");
  r.requireMarker(kSceneMarker);
  TriangleMesh mesh;
  mesh.vertices.resize(r.count(3 * sizeof(double)));
  for (Eigen::Vector3d& v : mesh.vertices) v = getVector(r);
  mesh.triangles.resize(r.count(3 * sizeof(std::int32_t)));
  for (auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) t[k] = r.get<std::int32_t>();
  }
  mesh.triangle_material = r.getArray<int>();
  if (mesh.triangle_material.size() != mesh.triangles.size()) r.fail("not one material index per triangle");
  MaterialLibrary library;
  const std::size_t materials = r.count(1);
  for (std::size_t m = 0; m < materials; ++m) {
    AcousticMaterial material;
    material.name = r.getString();
    material.absorption = getBands(r);
    material.scattering = getBands(r);
    for (std::optional<ThirdOctaveValues>* thirds : {&material.absorption_thirds, &material.scattering_thirds}) {
      if (!r.getBool()) continue;
      ThirdOctaveValues values{};
      for (OctaveBandValues& third : values) third = getBands(r);
      *thirds = values;
    }
    material.source = r.getString();
    if (library.contains(material.name)) r.fail("material '" + material.name + "' is named twice");
    library.add(material);  // validated: coefficients in [0, 1]
    mesh.material_names.push_back(material.name);
  }
  const bool closed = r.getBool();
  std::unique_ptr<AcousticScene> scene;
  if (r.getBool()) {
    RoomShape shape;
    shape.size_m = getVector(r);
    shape.has_ceiling = r.getBool();
    if (shape.has_ceiling != closed) r.fail("a room shape's scene is closed exactly when it has a ceiling");
    shape.objects.resize(r.count(1));
    for (CuboidObject& o : shape.objects) {
      o.label = r.getString();
      o.material = r.getString();
      o.center_m = getVector(r);
      o.size_m = getVector(r);
      o.yaw_rad = r.get<double>();
      o.confidence = r.get<double>();
      o.runner_up = r.getString();
      o.runner_up_confidence = r.get<double>();
      o.relief_scattering = getBands(r);
      if (!o.center_m.allFinite() || !o.size_m.allFinite() || (o.size_m.array() <= 0.0).any() || !std::isfinite(o.yaw_rad)) {
        r.fail("object '" + o.label + "' has a size that is not positive or a position that is not finite");
      }
    }
    if (!shape.size_m.allFinite() || (shape.size_m.array() <= 0.0).any()) r.fail("the room shape's size must be positive");
    r.requireEnd();
    scene = std::make_unique<AcousticScene>(std::move(mesh), library, MaterialOverrides{}, std::move(shape));
  } else {
    r.requireEnd();
    scene = std::make_unique<AcousticScene>(std::move(mesh), library, MaterialOverrides{}, closed);
  }
  return scene;
}

std::vector<std::uint8_t> encodeRequest(const SimulationRequest& request) {
  ByteWriter w;
  putRequest(w, request);
  return w.take();
}

SimulationRequest decodeRequest(const std::uint8_t* data, std::size_t size) {
  ByteReader r(data, size, "simulation request");
  SimulationRequest request = getRequest(r);
  r.requireEnd();
  return request;
}

std::vector<std::uint8_t> encodeResult(const SimulationResult& result) {
  ByteWriter w;
  w.put<std::uint32_t>(kResultMarker);
  const AudioBuffer& ir = result.impulse_response;
  w.put<double>(ir.sample_rate_hz);
  w.put<std::uint64_t>(ir.channels.size());
  for (const std::vector<float>& channel : ir.channels) w.putArray(channel.data(), channel.size());
  w.put<std::uint64_t>(result.paths.size());
  for (const SpecularPath& p : result.paths) {
    w.put<std::int32_t>(p.order);
    putVector(w, p.image_position);
    w.put<double>(p.distance_m);
    w.put<double>(p.delay_s);
    putBands(w, p.pressure_gain);
    putVector(w, p.arrival_direction);
    w.put<std::uint64_t>(p.triangles.size());
    for (std::size_t t : p.triangles) w.put<std::uint64_t>(t);
  }
  const EnergyHistogram& late = result.late;
  w.put<double>(late.binS());
  w.put<std::uint64_t>(late.bins());
  for (std::size_t bin = 0; bin < late.bins(); ++bin) {
    for (int b = 0; b < kOctaveBandCount; ++b) {
      w.put<double>(late.energy(bin, b));
      putVector(w, late.flux(bin, b));
    }
  }
  const RayTracingStats& s = result.stats;
  for (std::size_t v : {s.rays, s.reflections, s.leaked_rays, s.escaped_rays, s.stopped_by_time, s.stopped_by_energy,
                        s.sphere_detections}) {
    w.put<std::uint64_t>(v);
  }
  putBands(w, s.energy_left_at_time_limit);
  w.put<double>(s.receiver_radius_m);
  putBands(w, s.traced_until_s);
  putBands(w, result.eyring_t60_s);
  w.put<double>(result.speed_of_sound_m_s);
  // The wave part's figures, but not its wall time: the same request gives the same bytes.
  const WaveLowBandStats& low = result.low_band;
  w.putBool(low.used);
  w.put<double>(low.crossover_hz);
  w.put<double>(low.grid_spacing_m);
  w.put<std::uint64_t>(low.grid_cells);
  w.put<std::uint64_t>(low.solver_runs);
  w.put<double>(low.overlap_level_db);
  return w.take();
}

SimulationResult decodeResult(const std::uint8_t* data, std::size_t size) {
  ByteReader r(data, size, "simulation result");
  r.requireMarker(kResultMarker);
  SimulationResult result;
  AudioBuffer& ir = result.impulse_response;
  ir.sample_rate_hz = r.get<double>();
  ir.channels.resize(r.count(sizeof(std::uint64_t)));
  for (std::vector<float>& channel : ir.channels) {
    channel = r.getArray<float>();
    if (channel.size() != ir.channels.front().size()) r.fail("its channels differ in length");
  }
  result.paths.resize(r.count(1));
  for (SpecularPath& p : result.paths) {
    p.order = r.get<std::int32_t>();
    p.image_position = getVector(r);
    p.distance_m = r.get<double>();
    p.delay_s = r.get<double>();
    p.pressure_gain = getBands(r);
    p.arrival_direction = getVector(r);
    p.triangles.resize(r.count(sizeof(std::uint64_t)));
    for (std::size_t& t : p.triangles) t = static_cast<std::size_t>(r.get<std::uint64_t>());
  }
  const double bin_s = r.get<double>();
  const std::size_t bins = r.count(kOctaveBandCount * 4 * sizeof(double));
  if (!(bin_s > 0.0)) r.fail("its histogram's bin width is not positive");
  result.late = EnergyHistogram(bin_s, bins);
  for (std::size_t bin = 0; bin < bins; ++bin) {
    for (int b = 0; b < kOctaveBandCount; ++b) {
      const double energy = r.get<double>();
      result.late.set(bin, b, energy, getVector(r));
    }
  }
  RayTracingStats& s = result.stats;
  for (std::size_t* v : {&s.rays, &s.reflections, &s.leaked_rays, &s.escaped_rays, &s.stopped_by_time,
                         &s.stopped_by_energy, &s.sphere_detections}) {
    *v = static_cast<std::size_t>(r.get<std::uint64_t>());
  }
  s.energy_left_at_time_limit = getBands(r);
  s.receiver_radius_m = r.get<double>();
  s.traced_until_s = getBands(r);
  result.eyring_t60_s = getBands(r);
  result.speed_of_sound_m_s = r.get<double>();
  WaveLowBandStats& low = result.low_band;
  low.used = r.getBool();
  low.crossover_hz = r.get<double>();
  low.grid_spacing_m = r.get<double>();
  low.grid_cells = static_cast<std::size_t>(r.get<std::uint64_t>());
  low.solver_runs = static_cast<std::size_t>(r.get<std::uint64_t>());
  low.overlap_level_db = r.get<double>();
  r.requireEnd();
  return result;
}

std::vector<std::uint8_t> encodeJob(const std::vector<std::uint8_t>& scene_bytes, const SimulationRequest& request) {
  ByteWriter w;
  w.put<std::uint32_t>(kJobMarker);
  w.putBytes(scene_bytes);
  putRequest(w, request);
  return w.take();
}

JobParts splitJob(const std::uint8_t* data, std::size_t size) {
  ByteReader r(data, size, "simulation job");
  r.requireMarker(kJobMarker);
  JobParts parts;
  parts.scene_size = r.count(1);
  const std::size_t scene_at = sizeof(std::uint32_t) + sizeof(std::uint64_t);
  parts.scene = data + scene_at;
  ByteReader rest(parts.scene + parts.scene_size, size - scene_at - parts.scene_size, "simulation job");
  parts.request = getRequest(rest);
  rest.requireEnd();
  return parts;
}

}  // namespace room_reverb::core
