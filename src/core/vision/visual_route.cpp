#include "room_reverb/vision/visual_route.h"

#include <chrono>

namespace room_reverb::core {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

RoomLayout roomLayoutFromCloud(const PointCloud& cloud, const cv::Mat& top_color, double baseline_m,
                               const VisualRouteOptions& options, VisualRouteTimes* times) {
  (void)top_color;
  (void)baseline_m;
  auto start = std::chrono::steady_clock::now();
  RoomLayout layout = fitRoomLayout(cloud, options.layout);
  if (times != nullptr) times->layout_s = secondsSince(start);
  return layout;
}

VisualRoute runVisualRoute(const cv::Mat& top, const cv::Mat& bottom, double baseline_m,
                           const VisualRouteOptions& options) {
  VisualRoute route;
  auto start = std::chrono::steady_clock::now();
  route.depth = computeSphericalDepth(top, bottom, baseline_m, options.stereo);
  route.times.stereo_s = secondsSince(start);
  start = std::chrono::steady_clock::now();
  route.cloud = depthToPointCloud(route.depth, top, baseline_m, options.cloud);
  route.times.cloud_s = secondsSince(start);
  route.layout = roomLayoutFromCloud(route.cloud, top, baseline_m, options, &route.times);
  return route;
}

}  // namespace room_reverb::core
