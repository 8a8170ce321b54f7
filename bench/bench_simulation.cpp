// Speed of the simulation engine on the measured room of the BRAS database, CR2 (scene 9):
//  - raw Embree: rtcIntersect1 along random specular paths from the source (no materials,
//    no histogram), the ceiling for any ray tracer on this mesh;
//  - the project's wrapper (EmbreeScene::intersect) on paths of the same kind;
//  - the project's ray tracer (traceRays) on one thread, and its ratio to raw Embree;
//  - a full `accurate` simulation (image sources + 100 000 rays + first-order ambisonic
//    synthesis, 2 s, 2 threads): wall time and peak resident memory;
//  - the modal low band of the diagnosis for CR2's box.
// Run: scripts/bench, or this binary alone (20-40 s).
// Single-thread rates are per CPU second of the working thread; the simulation is timed on
// the wall clock. Needs ROOM_REVERB_SOURCE_DIR (the repository, for the mesh) and links
// Embree itself.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <fstream>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/ray_tracer.h"
#include "room_reverb/acoustics/room_modes.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/acoustics/triangle_mesh.h"
#include "bras_cr2_scene.h"

namespace {

using namespace room_reverb::core;

constexpr double kPi = 3.14159265358979323846;

using room_reverb::bench::cr2Scene;
using room_reverb::bench::sourceDir;
const Eigen::Vector3d& kSource = room_reverb::bench::kCr2Source;
const Eigen::Vector3d& kReceiver = room_reverb::bench::kCr2Receiver;

// ---------------------------------------------------------------------------------------
// Raw Embree on the scene's own triangles, built as the wrapper builds its two BVHs
// (embree_scene.h): watertight (robust traversal, high build quality) and fast (neither:
// the one the ray tracer's legs use), so that only the work around rtcIntersect1 differs.
// ---------------------------------------------------------------------------------------
class RawEmbree {
 public:
  RawEmbree(const TriangleMesh& mesh, bool robust) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("Embree: cannot create a device");
    scene_ = rtcNewScene(device_);
    rtcSetSceneFlags(scene_, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(scene_, robust ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.vertices.size()));
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.triangleCount()));
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
  }
  ~RawEmbree() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  RawEmbree(const RawEmbree&) = delete;
  RawEmbree& operator=(const RawEmbree&) = delete;
  RTCScene scene() const { return scene_; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

// Built on first use from a loaded scene.
const RawEmbree& cr2Raw(const AcousticScene& scene, bool robust = true) {
  static const RawEmbree raw_robust(scene.mesh(), true);
  static const RawEmbree raw_fast(scene.mesh(), false);
  return robust ? raw_robust : raw_fast;
}

// CPU time of the calling thread, s. The single-thread rates below are per CPU second of
// the one thread doing the work: what "per thread" means, and steadier than wall time
// when something else shares the machine.
double threadCpuS() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double processCpuS() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct PathCounts {
  std::size_t bounces = 0;  // hits, i.e. reflections
  std::size_t leaks = 0;    // paths that found no wall (restarted from the source)
};

// `paths` random specular paths of `bounces` reflections each, from the source.
PathCounts rawSpecularPaths(RTCScene scene, std::mt19937& rng, int paths, int bounces) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  PathCounts counts;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (int p = 0; p < paths; ++p) {
    const float z = 2.0f * u(rng) - 1.0f;
    const float phi = 2.0f * static_cast<float>(kPi) * u(rng);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    float o[3] = {static_cast<float>(kSource.x()), static_cast<float>(kSource.y()), static_cast<float>(kSource.z())};
    float d[3] = {r * std::cos(phi), r * std::sin(phi), z};
    for (int b = 0; b < bounces; ++b) {
      RTCRayHit q;
      q.ray.org_x = o[0];
      q.ray.org_y = o[1];
      q.ray.org_z = o[2];
      q.ray.tnear = 0.0f;
      q.ray.dir_x = d[0];
      q.ray.dir_y = d[1];
      q.ray.dir_z = d[2];
      q.ray.time = 0.0f;
      q.ray.tfar = std::numeric_limits<float>::infinity();
      q.ray.mask = 0xFFFFFFFFu;
      q.ray.id = 0;
      q.ray.flags = 0;
      q.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      q.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &q);
      if (q.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        ++counts.leaks;
        break;
      }
      ++counts.bounces;
      // Unit geometric normal, turned against the ray; mirror the direction; restart just
      // off the wall on the ray's side.
      float n[3] = {q.hit.Ng_x, q.hit.Ng_y, q.hit.Ng_z};
      const float inv = 1.0f / std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      float dn = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) * inv;
      const float sign = dn < 0.0f ? inv : -inv;
      for (int k = 0; k < 3; ++k) n[k] *= sign;
      dn = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
      for (int k = 0; k < 3; ++k) {
        o[k] += q.ray.tfar * d[k] + 1e-4f * n[k];
        d[k] -= 2.0f * dn * n[k];
      }
    }
  }
  return counts;
}

// Args: reflections per path, robust build (1) or not (0). One iteration: 1000 paths.
void BM_RawEmbreeSpecular(benchmark::State& state) {
  const AcousticScene* cr2 = cr2Scene(state);
  if (!cr2) return;
  const bool robust = state.range(1) != 0;
  const RTCScene scene = cr2Raw(*cr2, robust).scene();
  const int bounces = static_cast<int>(state.range(0));
  std::mt19937 rng(1);
  PathCounts total;
  for (auto _ : state) {
    const PathCounts counts = rawSpecularPaths(scene, rng, 1000, bounces);
    total.bounces += counts.bounces;
    total.leaks += counts.leaks;
  }
  state.counters["bounces_per_s"] = benchmark::Counter(static_cast<double>(total.bounces), benchmark::Counter::kIsRate);
  state.counters["leaks"] = static_cast<double>(total.leaks);
  state.SetItemsProcessed(static_cast<std::int64_t>(total.bounces));
}
BENCHMARK(BM_RawEmbreeSpecular)->ArgNames({"bounces", "robust"})->Args({100, 1})->Args({100, 0})->Unit(benchmark::kMillisecond)->MinTime(1.0);

// Paths of the same kind through the project's wrapper (double in and out, normal looked
// up): its watertight intersect() (fast 0) or the ray tracer's intersectFast() (fast 1).
void BM_EmbreeSceneSpecular(benchmark::State& state) {
  const AcousticScene* cr2 = cr2Scene(state);
  if (!cr2) return;
  const EmbreeScene& geometry = cr2->geometry();
  const int bounces = static_cast<int>(state.range(0));
  const bool fast = state.range(1) != 0;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PathCounts total;
  for (auto _ : state) {
    for (int p = 0; p < 1000; ++p) {
      const double z = 2.0 * u(rng) - 1.0;
      const double phi = 2.0 * kPi * u(rng);
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      Eigen::Vector3d position = kSource;
      Eigen::Vector3d direction(r * std::cos(phi), r * std::sin(phi), z);
      for (int b = 0; b < bounces; ++b) {
        const RayHit hit = fast ? geometry.intersectFast(position, direction, 0.0) : geometry.intersect(position, direction, 0.0);
        if (!hit.hit) {
          ++total.leaks;
          break;
        }
        ++total.bounces;
        const Eigen::Vector3d normal = hit.normal.dot(direction) < 0.0 ? hit.normal : Eigen::Vector3d(-hit.normal);
        position += hit.distance_m * direction + 1e-4 * normal;
        direction -= 2.0 * direction.dot(normal) * normal;
      }
    }
  }
  state.counters["bounces_per_s"] = benchmark::Counter(static_cast<double>(total.bounces), benchmark::Counter::kIsRate);
  state.counters["leaks"] = static_cast<double>(total.leaks);
  state.SetItemsProcessed(static_cast<std::int64_t>(total.bounces));
}
BENCHMARK(BM_EmbreeSceneSpecular)->ArgNames({"bounces", "fast"})->Args({100, 0})->Args({100, 1})->Unit(benchmark::kMillisecond)->MinTime(1.0);

// The project's tracer, one thread, the settings simulateRoom gives it for CR2 (2 s,
// image-source order 3, air at 20 C / 50 %). Arg: rays per iteration. Each iteration also
// times raw Embree (as BM_RawEmbreeSpecular, the fast build the tracer's legs use, about
// 0.1 s, outside the benchmark's timing) right before the tracer, so that the ratio
// compares the two at the same machine speed: on a shared machine that speed drifts by
// tens of percent.
void BM_TraceRaysOneThread(benchmark::State& state) {
  const AcousticScene* cr2 = cr2Scene(state);
  if (!cr2) return;
  const AcousticScene& scene = *cr2;
  const RTCScene raw_scene = cr2Raw(scene, false).scene();
  std::mt19937 raw_rng(1);
  rawSpecularPaths(raw_scene, raw_rng, 200, 100);  // warm-up
  const PropagationModel model = PropagationModel::from(AirConditions{}, SourceDirectivity{});
  RayTracingOptions options;
  options.ray_count = static_cast<std::size_t>(state.range(0));
  options.max_time_s = 2.0;
  options.image_source_order = 3;
  options.threads = 1;
  std::size_t reflections = 0, rays = 0, leaks = 0, raw_bounces = 0;
  double seconds = 0.0, raw_seconds = 0.0;
  std::uint32_t seed = 1;
  for (auto _ : state) {
    state.PauseTiming();
    const double raw_start = threadCpuS();
    for (int batch = 0; batch < 6; ++batch) raw_bounces += rawSpecularPaths(raw_scene, raw_rng, 1000, 100).bounces;
    raw_seconds += threadCpuS() - raw_start;
    state.ResumeTiming();
    options.seed = seed++;
    const double start = threadCpuS();  // threads = 1: traceRays works on this thread
    const RayTracingResult result = traceRays(scene, kSource, kReceiver, model, options);
    seconds += threadCpuS() - start;
    benchmark::DoNotOptimize(result.histogram.totalEnergy(0));
    reflections += result.stats.reflections;
    rays += result.stats.rays;
    leaks += result.stats.leaked_rays;
  }
  const double rate = static_cast<double>(reflections) / seconds;
  const double raw_rate = static_cast<double>(raw_bounces) / raw_seconds;
  state.counters["bounces_per_s"] = rate;  // reflections per CPU second of the tracing thread
  state.counters["raw_bounces_per_s"] = raw_rate;
  state.counters["ratio_to_raw"] = rate / raw_rate;
  state.counters["reflections_per_ray"] = static_cast<double>(reflections) / static_cast<double>(rays);
  state.counters["leaked_rays"] = static_cast<double>(leaks);
  state.SetItemsProcessed(static_cast<std::int64_t>(reflections));
}
BENCHMARK(BM_TraceRaysOneThread)->ArgName("rays")->Arg(4000)->Unit(benchmark::kMillisecond)->Iterations(3);

// A field of /proc/self/status in kB ("VmHWM": peak resident set, "VmRSS": current one),
// as MB; -1 if /proc cannot tell.
double procStatusMb(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field + ":", 0) == 0) return std::stod(line.substr(field.size() + 1)) / 1024.0;
  }
  return -1.0;
}

// Resets VmHWM to the current resident set (Linux >= 4.0); false where not allowed.
bool resetPeakResident() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

// `room_reverb simulate --mesh cr2_scene9.ac --y-up --mode accurate --rays 100000
// --duration 2 --ambisonic-order 1 --threads 2`, less the file output; the scene is
// built beforehand (see BM_BuildCr2Scene). Arg 1 (the default) continues established
// decays analytically, arg 0 traces every band to the end (--trace-to-end).
void BM_SimulateCr2Accurate(benchmark::State& state) {
  const AcousticScene* cr2 = cr2Scene(state);
  if (!cr2) return;
  const AcousticScene& scene = *cr2;
  SimulationSettings settings;
  settings.mode = SimulationMode::kAccurate;
  settings.image_source_order = 3;
  settings.duration_s = 2.0;
  settings.ambisonic_order = 1;
  settings.rays.ray_count = 100000;
  settings.rays.threads = 2;
  settings.rays.continue_established_decays = state.range(0) != 0;
  if (state.range(1) != 0) settings.bands = BandResolution::kThirdOctave;  // three runs, one per third
  const double hwm_before_mb = procStatusMb("VmHWM");
  const double rss_before_mb = procStatusMb("VmRSS");
  // With the reset, VmHWM afterwards is the peak of the simulation itself (the scene and
  // everything else already resident included), not of earlier benchmarks.
  const bool reset = resetPeakResident();
  double peak_mb = 0.0;
  std::size_t reflections = 0, paths = 0, leaks = 0;
  const double cpu_start = processCpuS();
  for (auto _ : state) {
    const SimulationResult result = simulateRoom(scene, kSource, kReceiver, settings);
    benchmark::DoNotOptimize(result.impulse_response.durationS());
    reflections = result.stats.reflections;
    paths = result.paths.size();
    leaks = result.stats.leaked_rays;
    peak_mb = std::max(peak_mb, procStatusMb("VmHWM"));
  }
  // CPU seconds of all threads per run: near 2x the wall time when both threads keep busy.
  state.counters["cpu_s"] = (processCpuS() - cpu_start) / static_cast<double>(state.iterations());
  state.counters["peak_MB"] = peak_mb;                        // VmHWM after
  state.counters["hwm_before_MB"] = hwm_before_mb;            // VmHWM before (whole process so far)
  state.counters["growth_MB"] = peak_mb - rss_before_mb;      // peak over what was resident before
  state.counters["hwm_reset"] = reset ? 1.0 : 0.0;           // 0: peak_MB may be an earlier peak
  state.counters["reflections"] = static_cast<double>(reflections);
  state.counters["image_paths"] = static_cast<double>(paths);
  state.counters["leaked_rays"] = static_cast<double>(leaks);
}
BENCHMARK(BM_SimulateCr2Accurate)
    ->ArgNames({"continued", "thirds"})
    ->Args({1, 0})
    ->Args({0, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

// The preview modes, one response each: fast (image sources + the room's own decay from
// 8000 rays, no receiver detection; arg 0) and eyring (image sources + Eyring tail; arg 1),
// 2 s, first order, 2 threads, on CR2 and on the demo's sample room.
void simulatePreview(benchmark::State& state, const AcousticScene& scene, const Eigen::Vector3d& source,
                     const Eigen::Vector3d& listener) {
  SimulationSettings settings;
  settings.mode = state.range(0) == 0 ? SimulationMode::kFast : SimulationMode::kEyring;
  settings.duration_s = 2.0;
  settings.ambisonic_order = 1;
  settings.rays.threads = 2;
  const double cpu_start = processCpuS();
  for (auto _ : state) {
    const SimulationResult result = simulateRoom(scene, source, listener, settings);
    benchmark::DoNotOptimize(result.impulse_response.durationS());
  }
  state.counters["cpu_s"] = (processCpuS() - cpu_start) / static_cast<double>(state.iterations());
}

void BM_SimulateCr2Preview(benchmark::State& state) {
  const AcousticScene* cr2 = cr2Scene(state);
  if (cr2) simulatePreview(state, *cr2, kSource, kReceiver);
}
BENCHMARK(BM_SimulateCr2Preview)->ArgName("eyring")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

void BM_SimulateSampleRoomPreview(benchmark::State& state) {
  static const AcousticScene scene =
      roomModelToScene(loadRoomModel(sourceDir() + "/data/sample_room/visible.yaml"), MaterialLibrary::loadDefault(), {});
  simulatePreview(state, scene, {4.6, 2.9, 1.5}, {2.7, 2.1, 1.4});
}
BENCHMARK(BM_SimulateSampleRoomPreview)->ArgName("eyring")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

// Loading the AC3D file and building the scene (materials, planes, BVH).
void BM_BuildCr2Scene(benchmark::State& state) {
  const AcousticScene* cr2 = cr2Scene(state);
  if (!cr2) return;
  const MaterialLibrary library = MaterialLibrary::loadDefault();
  const std::string path = sourceDir() + "/data/bras_cr2/geometry/cr2_scene9.ac";
  for (auto _ : state) {
    const AcousticScene scene(loadMesh(path, UpAxis::kY), library);
    benchmark::DoNotOptimize(scene.volumeM3());
  }
  state.counters["triangles"] = static_cast<double>(cr2->mesh().triangleCount());
  state.counters["planes"] = static_cast<double>(cr2->planes().size());
}
BENCHMARK(BM_BuildCr2Scene)->Unit(benchmark::kMillisecond)->UseRealTime();

// The diagnosis's modal low band (room_modes.h) for CR2's box: every mode up to 1.3 x
// sqrt(2) times the Schroeder frequency, 2 s of omni response, as the diagnosis
// re-analyses it once per pair and candidate damping.
void BM_ModalLowBandCr2(benchmark::State& state) {
  const AcousticScene* cr2 = cr2Scene(state);
  if (!cr2) return;
  const ModalRoom room = modalRoomFromScene(*cr2, 343.2);
  const OctaveBandValues t60 = eyringReverberationTimes(*cr2, AirConditions{});
  const double crossover = schroederFrequencyHz(0.5 * (t60[3] + t60[4]), cr2->volumeM3());
  ModalSynthesisOptions options;
  options.frames = 96000;
  options.max_frequency_hz = 1.3 * std::sqrt(2.0) * crossover;
  for (auto _ : state) benchmark::DoNotOptimize(synthesizeRoomModes(room, kSource, kReceiver, options));
  state.counters["modes"] = static_cast<double>(roomModes(room, options.max_frequency_hz).size());
  state.counters["crossover_hz"] = crossover;
}
BENCHMARK(BM_ModalLowBandCr2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
