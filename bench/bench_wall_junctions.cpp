// What placing a far wall by the ceiling's junction in the image costs
// (vision/wall_junctions.h): a 9 x 3.6 x 3 m room rendered by the capture generator with
// the rig 7.3 m from its far wall, the box the depth gives placing that wall at 6 m, one
// search (35 % inside to 50 % beyond, 1 cm steps) at 1024 and 2048 px. The route looks only on
// walls without a plane at the ceiling's edge, so this is the cost per such wall.
// Counter: err_cm, the found wall against the true one [cm].
// Run: .ws/devel/lib/room_reverb/bench_wall_junctions
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "room_box_fit.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "wall_junctions.h"

using namespace room_reverb::core;

namespace {

constexpr double kBaseline = 0.2;

RoomModel longRoom() {
  return parseRoomModel(R"(
frame: room
room_box: {size_m: [9.0, 3.6, 3.0], has_ceiling: true}
surfaces:
  floor: {material: wood_floor}
  ceiling: {material: acoustic_ceiling_tiles}
  wall_x_min: {material: plaster_smooth}
  wall_x_max: {material: plaster_smooth}
  wall_y_min: {material: plaster_smooth}
  wall_y_max: {material: plaster_smooth}
rig_in_room: {position_m: [7.3, 1.8, 1.3], rotation_xyzw: [0, 0, 0, 1]}
)");
}

const cv::Mat& topImage(int width) {
  static std::map<int, cv::Mat> cache;
  auto it = cache.find(width);
  if (it == cache.end()) {
    CaptureOptions options;
    options.width = width;
    options.baseline_m = kBaseline;
    it = cache.emplace(width, renderCapture(longRoom(), MaterialLibrary::loadDefault(), options).top.color).first;
  }
  return it->second;
}

void BM_CeilingJunction(benchmark::State& state) {
  const cv::Mat& image = topImage(static_cast<int>(state.range(0)));
  layout::AlignedBox box;  // the aligned frame: the rig at the origin
  box.x_lo = -6.0, box.x_hi = 1.7, box.y_lo = -1.8, box.y_hi = 1.8;
  box.floor_z = -1.3, box.top_z = 1.7;
  const Eigen::Isometry3d camera_from_aligned(Eigen::Translation3d(0.0, 0.0, -0.5 * kBaseline));
  layout::JunctionFit fit;
  for (auto _ : state) {
    // What the first wall of a layout costs: the image's preparation and one search.
    fit = layout::ceilingJunction(layout::junctionImage(image), camera_from_aligned, box, 2, {});
    benchmark::DoNotOptimize(fit);
  }
  state.counters["found"] = fit.found ? 1.0 : 0.0;
  state.counters["err_cm"] = 100.0 * std::abs(fit.position_m + 7.3);
}
BENCHMARK(BM_CeilingJunction)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
