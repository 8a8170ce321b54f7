// The visual route's speed and accuracy at 2048 x 1024, the size its targets are set for
// (target: a pair to a room model with materials in under 2 s on 2 cores). Each bundled
// capture scene is rendered once (not timed); BM_PairToPointCloud times spherical stereo
// plus the point cloud, and reports the depth accuracy against the generator's truth as
// counters:
//   valid_pct      valid pixels outside the polar caps [%]
//   median_pct     median relative range error on valid pixels [%]
//   p90_pct        90th percentile of it [%]
//   points         points in the cloud
// BM_PairToPointCloudExposedApart does the same with the bottom camera exposed apart from
// the top one, as every real pair is; BM_PairToPointCloudWithoutPlanes without the tiles'
// planes (SphericalStereoOptions::planar_refinement), for their cost in the same run. BM_PointCloudToRoomModel times the second half, the
// point cloud to a room model with materials (roomLayoutFromCloud: layout fit, material
// step and relief, after the stereo's disparity offset is looked for), with its accuracy as counters:
//   size_err_cm    largest error of the room's three dimensions [cm] (ceiling-less: two)
//   yaw_err_deg    rig yaw error [deg]
//   iou_min        lowest 3D IoU of a true object at least 0.5 m in its largest side with
//                  the best fitted cuboid (1 when the scene has none); thin boards and
//                  doors (2-4 cm) count, and at the stereo's range noise they merge with
//                  their wall or the unit they stand on
//   iou_furniture  the same over objects at least 0.5 m in every extent
//   objects        fitted objects, over true_objects in the scene
//   material_pct   share of the true box faces' area whose material has the true look
//                  (texture family) [%]
//   range_bias_s   median wall-clock time of the disparity offset's estimate [s]
//   layout_s       median wall-clock time of the layout fit (cloud -> cuboids) [s]
//   materials_s    median wall-clock time of the material step [s]
//   relief_s       median wall-clock time of the relief step [s]
// BM_PairRectification times the pair's rectification (vision/pair_rectification.h: the
// features at feature_width px, the fit, the bottom image turned bicubic) on each scene rendered
// with its bottom camera turned by (0.4, -0.6, 0.3) degrees against the top one:
//   turn_err_mrad  the turn found against the truth [mrad]
// BM_WholeRoute times what `room_reverb room-model` does with a pair, every step with its
// defaults: the pair ingested (levelled by its images' straight edges, rectified), the
// stereo, the cloud, the disparity offset, the layout, materials and relief; the scene
// rendered as in BM_PairRectification (the bottom camera turned). Counters:
//   ingest_s       median wall-clock time of the ingest (levelling and rectification) [s]
//   stereo_s, cloud_s  of the stereo and the point cloud [s]
//   model_s        of the rest: disparity offset, layout, materials and relief [s]
//   layout_s       of the layout fit alone (cloud -> cuboids) [s]
//   size_err_cm    as above
// Run: scripts/bench (all benchmarks) or .ws/devel/lib/room_reverb/bench_visual_route
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <string>
#include <vector>

#include "room_reverb/common/error.h"
#include "room_reverb/common/memory_reuse.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/capture_ingest.h"
#include "room_reverb/vision/depth_cloud.h"
#include "room_reverb/vision/equirect_rotation.h"
#include "room_reverb/vision/pair_rectification.h"
#include "room_reverb/vision/oriented_box_iou.h"
#include "room_reverb/vision/spherical_stereo.h"
#include "room_reverb/vision/texture_family.h"
#include "room_reverb/vision/visual_route.h"

namespace {

using namespace room_reverb::core;

constexpr double kPi = 3.14159265358979323846;
const std::vector<std::string> kScenes = {"mr", "kt", "plain_office", "lounge_furniture", "yawed_rig_studio", "courtyard"};

// `exposed_apart`: the two cameras on their own auto-exposure, as every real pair is (the
// bottom one a third of a stop darker and white-balanced warmer), which the stereo's
// exposure matching carries over before it matches.
CaptureScene scene(const std::string& name, bool exposed_apart = false) {
  CaptureScene s = loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/" + name + ".yaml");
  s.options.width = 2048;
  if (exposed_apart) {
    s.options.camera.bottom_exposure = 0.79;
    s.options.camera.bottom_white_balance = {1.08, 1.0, 0.92};
  }
  return s;
}

const StereoCapture& capture(const std::string& name, bool exposed_apart = false) {
  static std::map<std::pair<std::string, bool>, StereoCapture> cache;
  auto it = cache.find({name, exposed_apart});
  if (it == cache.end()) {
    const CaptureScene s = scene(name, exposed_apart);
    it = cache.emplace(std::make_pair(name, exposed_apart), renderCapture(s.room, MaterialLibrary::loadDefault(), s.options)).first;
  }
  return it->second;
}

const PointCloud& stereoCloud(const std::string& name) {
  static std::map<std::string, PointCloud> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    const StereoCapture& c = capture(name);
    const SphericalDepth depth = computeSphericalDepth(c.top.color, c.bottom.color, 0.2);
    it = cache.emplace(name, depthToPointCloud(depth, c.top.color, 0.2)).first;
  }
  return it->second;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

double yawOf(const Eigen::Quaterniond& q) { return 2.0 * std::atan2(q.z(), q.w()); }

double faceArea(const Eigen::Vector3d& size, int k) {
  if (k < 2) return size.x() * size.y();
  return (k < 4 ? size.y() : size.x()) * size.z();
}

void pairToPointCloud(benchmark::State& state, bool exposed_apart, bool planes = true, bool texture_test = true) {
  const std::string name = kScenes[static_cast<std::size_t>(state.range(0))];
  const StereoCapture& c = capture(name, exposed_apart);
  state.SetLabel(name);
  SphericalStereoOptions options;
  options.planar_refinement = planes;
  if (!texture_test) options.min_texture_snr = 0.0;
  SphericalDepth depth;
  PointCloud cloud;
  for (auto _ : state) {
    depth = computeSphericalDepth(c.top.color, c.bottom.color, 0.2, options);
    cloud = depthToPointCloud(depth, c.top.color, 0.2);
    benchmark::DoNotOptimize(cloud.points.data());
  }
  std::vector<double> errors;
  long outside = 0, valid = 0;
  const cv::Mat& truth = c.top.range_m;
  for (int v = 0; v < truth.rows; ++v) {
    const double theta = (v + 0.5) * kPi / truth.rows;
    if (theta < options.polar_cap_deg * kPi / 180.0 || theta > kPi - options.polar_cap_deg * kPi / 180.0) continue;
    for (int u = 0; u < truth.cols; ++u) {
      const float t = truth.at<float>(v, u);
      if (!std::isfinite(t)) continue;  // sky
      ++outside;
      if (depth.valid.at<std::uint8_t>(v, u) == 0) continue;
      ++valid;
      errors.push_back(std::abs(depth.range_m.at<float>(v, u) - t) / t);
    }
  }
  std::sort(errors.begin(), errors.end());
  state.counters["valid_pct"] = 100.0 * static_cast<double>(valid) / static_cast<double>(std::max(outside, 1L));
  state.counters["median_pct"] = errors.empty() ? 0.0 : 100.0 * errors[errors.size() / 2];
  state.counters["p90_pct"] = errors.empty() ? 0.0 : 100.0 * errors[errors.size() * 9 / 10];
  state.counters["points"] = static_cast<double>(cloud.points.size());
}

void BM_PairToPointCloud(benchmark::State& state) { pairToPointCloud(state, false); }
BENCHMARK(BM_PairToPointCloud)->DenseRange(0, static_cast<int>(kScenes.size()) - 1)->Unit(benchmark::kMillisecond)
    ->Iterations(3)->UseRealTime();

// The same without the tiles' planes (SphericalStereoOptions::planar_refinement): what
// they cost, measured in the same run.
void BM_PairToPointCloudWithoutPlanes(benchmark::State& state) { pairToPointCloud(state, false, false); }
BENCHMARK(BM_PairToPointCloudWithoutPlanes)->DenseRange(0, static_cast<int>(kScenes.size()) - 1)
    ->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// The same keeping every match (SphericalStereoOptions::min_texture_snr 0): what the
// texture test costs.
void BM_PairToPointCloudKeepingEveryMatch(benchmark::State& state) { pairToPointCloud(state, false, true, false); }
BENCHMARK(BM_PairToPointCloudKeepingEveryMatch)->DenseRange(0, static_cast<int>(kScenes.size()) - 1)
    ->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

void BM_PairToPointCloudExposedApart(benchmark::State& state) { pairToPointCloud(state, true); }
BENCHMARK(BM_PairToPointCloudExposedApart)->DenseRange(0, static_cast<int>(kScenes.size()) - 1)
    ->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

const Eigen::Vector3d kBottomTurnDeg(0.4, -0.6, 0.3);

const StereoCapture& turnedCapture(const std::string& name) {
  static std::map<std::string, StereoCapture> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    CaptureScene s = scene(name);
    s.options.camera.bottom_turn_deg = kBottomTurnDeg;
    it = cache.emplace(name, renderCapture(s.room, MaterialLibrary::loadDefault(), s.options)).first;
  }
  return it->second;
}


void BM_PairRectification(benchmark::State& state) {
  const std::string name = kScenes[static_cast<std::size_t>(state.range(0))];
  const StereoCapture& c = turnedCapture(name);
  state.SetLabel(name);
  PairRectificationOptions options;
  options.feature_width = static_cast<int>(state.range(1));
  PairRectification found;
  for (auto _ : state) {
    found = estimatePairRectification(c.top.color, c.bottom.color, options);
    const cv::Mat turned = rotateEquirect(c.bottom.color, found.bottom_rotation, cv::INTER_CUBIC);
    benchmark::DoNotOptimize(turned.data);
  }
  const double angle = kBottomTurnDeg.norm() * kPi / 180.0;
  const Eigen::Matrix3d truth = Eigen::AngleAxisd(angle, kBottomTurnDeg.normalized()).toRotationMatrix();
  state.counters["turn_err_mrad"] = 1e3 * Eigen::AngleAxisd(found.bottom_to_top.transpose() * truth).angle();
}
BENCHMARK(BM_PairRectification)
    ->ArgsProduct({benchmark::CreateDenseRange(0, static_cast<int>(kScenes.size()) - 1, 1), {1024, 2048}})
    ->ArgNames({"scene", "feature_width"})
    ->Unit(benchmark::kMillisecond);

// The route's default options, the shipped material models loaded.
VisualRouteOptions defaultRouteOptions() {
  VisualRouteOptions options;
  loadDefaultMaterialModels(options);
  return options;
}

// The largest error of the room's dimensions [m] (a room without a ceiling: two).
double largestSizeError(const RoomModel& got, const RoomModel& truth) {
  double error = 0.0;
  for (int k = 0; k < (truth.has_ceiling ? 3 : 2); ++k) error = std::max(error, std::abs(got.size_m[k] - truth.size_m[k]));
  return error;
}

void BM_WholeRoute(benchmark::State& state) {
  const std::string name = kScenes[static_cast<std::size_t>(state.range(0))];
  const CaptureScene truth = scene(name);
  const StereoCapture& c = turnedCapture(name);
  state.SetLabel(name);
  VisualRouteOptions options = defaultRouteOptions();
  VisualRoute route;
  std::vector<double> ingest_s, stereo_s, cloud_s, rest_s, layout_s;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const IngestedCapture pair = ingestCapture(c.top.color, c.bottom.color, CaptureIngestOptions{});
    ingest_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    options.level_from_cloud = pair.level_from_cloud;
    try {
      route = runVisualRoute(pair.top, pair.bottom, 0.2, options, pair.leveling.tilt);
    } catch (const InputError& e) {
      state.SkipWithError(e.what());
      return;
    }
    benchmark::DoNotOptimize(route.layout.model.objects.data());
    stereo_s.push_back(route.times.stereo_s);
    cloud_s.push_back(route.times.cloud_s);
    rest_s.push_back(route.times.range_bias_s + route.times.layout_s + route.times.materials_s + route.times.relief_s);
    layout_s.push_back(route.times.layout_s);
  }
  state.counters["ingest_s"] = median(ingest_s);
  state.counters["stereo_s"] = median(stereo_s);
  state.counters["cloud_s"] = median(cloud_s);
  state.counters["model_s"] = median(rest_s);
  state.counters["layout_s"] = median(layout_s);
  state.counters["size_err_cm"] = 100.0 * largestSizeError(route.layout.model, truth.room);
}
BENCHMARK(BM_WholeRoute)->DenseRange(0, static_cast<int>(kScenes.size()) - 1)->Unit(benchmark::kMillisecond)
    ->Iterations(3)->UseRealTime();

void BM_PointCloudToRoomModel(benchmark::State& state) {
  const std::string name = kScenes[static_cast<std::size_t>(state.range(0))];
  const CaptureScene truth = scene(name);
  const StereoCapture& c = capture(name);
  const PointCloud& cloud = stereoCloud(name);
  state.SetLabel(name);
  const VisualRouteOptions options = defaultRouteOptions();
  RoomLayout layout;
  std::vector<double> range_bias_s, layout_s, materials_s, relief_s;
  for (auto _ : state) {
    VisualRouteTimes times;
    try {
      layout = roomLayoutFromCloud(cloud, c.top.color, 0.2, options, Eigen::Matrix3d::Identity(), &times);
    } catch (const InputError& e) {
      state.SkipWithError(e.what());  // the courtyard: its facades are not found as walls
      return;
    }
    benchmark::DoNotOptimize(layout.model.objects.data());
    range_bias_s.push_back(times.range_bias_s);
    layout_s.push_back(times.layout_s);
    materials_s.push_back(times.materials_s);
    relief_s.push_back(times.relief_s);
  }
  const RoomModel& got = layout.model;
  double iou_min = 1.0, iou_furniture = 1.0;
  for (const CuboidObject& object : truth.room.objects) {
    if (object.size_m.maxCoeff() < 0.5) continue;
    double best = 0.0;
    for (const CuboidObject& fitted : got.objects) best = std::max(best, orientedBoxIoU3d(object, fitted));
    iou_min = std::min(iou_min, best);
    if (object.size_m.minCoeff() >= 0.5) iou_furniture = std::min(iou_furniture, best);
  }
  double right = 0.0, total = 0.0;
  for (int k = 0; k < 6; ++k) {
    const auto t = truth.room.surfaces.find(kRoomSurfaceNames[static_cast<std::size_t>(k)]);
    const auto g = got.surfaces.find(kRoomSurfaceNames[static_cast<std::size_t>(k)]);
    if (t == truth.room.surfaces.end()) continue;
    const double area = faceArea(truth.room.size_m, k);
    total += area;
    if (g != got.surfaces.end() && textureFamilyFor(g->second.material).family == textureFamilyFor(t->second.material).family) {
      right += area;
    }
  }
  state.counters["size_err_cm"] = 100.0 * largestSizeError(got, truth.room);
  state.counters["yaw_err_deg"] = std::abs(layout.rig_yaw_rad - yawOf(truth.room.rig_rotation)) * 180.0 / kPi;
  state.counters["iou_min"] = iou_min;
  state.counters["objects"] = static_cast<double>(got.objects.size());
  state.counters["true_objects"] = static_cast<double>(truth.room.objects.size());
  state.counters["iou_furniture"] = iou_furniture;
  state.counters["material_pct"] = 100.0 * right / std::max(total, 1e-9);
  state.counters["range_bias_s"] = median(range_bias_s);
  state.counters["layout_s"] = median(layout_s);
  state.counters["materials_s"] = median(materials_s);
  state.counters["relief_s"] = median(relief_s);
}
BENCHMARK(BM_PointCloudToRoomModel)->DenseRange(0, static_cast<int>(kScenes.size()) - 1)->Unit(benchmark::kMillisecond)
    ->Iterations(3)->UseRealTime();

}  // namespace

// As the command-line tool and the room_model node run the route: freed memory kept for
// reuse (common/memory_reuse.h).
int main(int argc, char** argv) {
  room_reverb::core::keepFreedMemoryForReuse();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
