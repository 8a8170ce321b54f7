// The visual route's speed and accuracy at 2048 x 1024, the size its targets are set for
// (issue 6: a pair to a point cloud in under 2 s, to a room model in under 2 s more, on 2
// cores). Each bundled capture scene is rendered once (not timed); the benchmark times
// spherical stereo plus the point cloud, and reports the depth accuracy against the
// generator's truth as counters:
//   valid_pct      valid pixels outside the polar caps [%]
//   median_pct     median relative range error on valid pixels [%]
//   p90_pct        90th percentile of it [%]
//   points         points in the cloud
// Run: scripts/bench (all benchmarks) or .ws/devel/lib/room_reverb/bench_visual_route
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "room_reverb/vision/capture_scene.h"
#include "room_reverb/vision/depth_cloud.h"
#include "room_reverb/vision/spherical_stereo.h"

namespace {

using namespace room_reverb::core;

constexpr double kPi = 3.14159265358979323846;
const std::vector<std::string> kScenes = {"mr", "kt", "plain_office", "lounge_furniture", "yawed_rig_studio", "courtyard"};

const StereoCapture& capture(const std::string& name) {
  static std::map<std::string, StereoCapture> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    CaptureScene scene = loadCaptureScene(std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/" + name + ".yaml");
    scene.options.width = 2048;
    it = cache.emplace(name, renderCapture(scene.room, MaterialLibrary::loadDefault(), scene.options)).first;
  }
  return it->second;
}

void BM_PairToPointCloud(benchmark::State& state) {
  const std::string name = kScenes[static_cast<std::size_t>(state.range(0))];
  const StereoCapture& c = capture(name);
  state.SetLabel(name);
  const SphericalStereoOptions options;
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
BENCHMARK(BM_PairToPointCloud)->DenseRange(0, static_cast<int>(kScenes.size()) - 1)->Unit(benchmark::kMillisecond)
    ->Iterations(3)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
