#include "room_reverb/vision/visual_route.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "rotation_check.h"

namespace room_reverb::core {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool isIdentity(const Eigen::Matrix3d& r) { return (r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-12; }

// The cloud with the stereo's disparity offset taken out where one is found (range_bias.h;
// the fit, the image's rays and the relief all use it), `storage` holding it; the cloud
// itself otherwise. `note` says what was corrected.
const PointCloud& withoutDisparityOffset(const PointCloud& cloud, double baseline_m, const Eigen::Matrix3d& level,
                                         const DisparityOffsetOptions& options, int image_rows, PointCloud& storage,
                                         std::string& note) {
  if (!options.enabled) return cloud;
  const DisparityOffset bias = estimateDisparityOffset(cloud, baseline_m, level, options);
  if (!bias.applied && !bias.azimuth_applied) return cloud;
  storage = removeDisparityOffset(cloud, baseline_m, bias, options.min_polar_rad);
  const bool both = bias.floor_fitted && bias.ceiling_fitted;
  std::string line = std::string("range: the ") +
                     (both ? "floor and ceiling lie" : (bias.ceiling_fitted ? "ceiling lies" : "floor lies")) +
                     " flat with the stereo's disparity offset by";
  char part[200];
  if (bias.applied) {
    // What the offset does to a point level with the rig 5 m away, for the user to judge.
    const double at_5m = rangeWithoutDisparityOffset(5.0, 0.5 * M_PI, baseline_m, bias.offset_rad);
    char planes[80];
    if (both) {
      std::snprintf(planes, sizeof planes, "floor %+.2f, ceiling %+.2f mrad", 1e3 * bias.floor_offset_rad,
                    1e3 * bias.ceiling_offset_rad);
    } else {
      std::snprintf(planes, sizeof planes, "from the %s alone", bias.ceiling_fitted ? "ceiling" : "floor");
    }
    std::snprintf(part, sizeof part, " %+.2f mrad (%+.2f px at this width; %s; %+.1f %% at 5 m)",
                  1e3 * bias.offset_rad, bias.offset_rad * image_rows / M_PI, planes,
                  std::isfinite(at_5m) ? 100.0 * (at_5m / 5.0 - 1.0) : 100.0);
    line += part;
  }
  if (bias.azimuth_applied) {
    // An offset that goes with the azimuth: a camera tilted against the other.
    const double amplitude = std::hypot(bias.cos_rad, bias.sin_rad);
    const double at_5m = rangeWithoutDisparityOffset(5.0, 0.5 * M_PI, baseline_m, amplitude);
    std::snprintf(part, sizeof part,
                  "%s %.2f mrad with the azimuth, greatest towards %.0f deg (a camera tilted against the other; "
                  "%+.1f %% at 5 m there)",
                  bias.applied ? " and" : "", 1e3 * amplitude, std::atan2(bias.sin_rad, bias.cos_rad) * 180.0 / M_PI,
                  std::isfinite(at_5m) ? 100.0 * (at_5m / 5.0 - 1.0) : 100.0);
    line += part;
  }
  line += "; every range corrected for it";
  note = line;
  return storage;
}

}  // namespace

void loadDefaultMaterialModels(VisualRouteOptions& options) {
  options.classifier = std::make_shared<const MaterialClassifier>(MaterialClassifier::load(MaterialClassifier::defaultPath()));
  options.families = std::make_shared<const MaterialFamilyTable>(
      loadMaterialFamilyTable(defaultMaterialFamilyTablePath(), MaterialLibrary::loadDefault()));
}

RoomLayout roomLayoutFromCloud(const PointCloud& cloud, const cv::Mat& top_color, double baseline_m,
                               const VisualRouteOptions& options, const Eigen::Matrix3d& tilt, VisualRouteTimes* times,
                               std::vector<SurfaceMaterialDecision>* materials) {
  vision_detail::requireRotation(tilt, "visual route: rig tilt");
  auto start = std::chrono::steady_clock::now();
  Eigen::Matrix3d level_tilt = tilt;
  std::string leveled;
  if (options.level_from_cloud) {
    PointCloud tilted = cloud;
    const Eigen::Matrix3f tilt_f = tilt.cast<float>();
    for (CloudPoint& point : tilted.points) point.p = tilt_f * point.p;
    const CloudLeveling by_cloud = levelFromCloud(tilted, options.cloud_leveling);
    level_tilt = by_cloud.tilt * tilt;
    char line[160];
    std::snprintf(line, sizeof line, "leveling: from the cloud's floor and ceiling, rig tilt %.2f deg",
                  by_cloud.tilt_rad * 180.0 / 3.14159265358979323846);
    leveled = line;
  }
  const double leveling_s = secondsSince(start);
  start = std::chrono::steady_clock::now();
  PointCloud corrected;
  std::string bias_note;
  const PointCloud& fitted_cloud = withoutDisparityOffset(cloud, baseline_m, level_tilt, options.disparity_offset,
                                                          top_color.rows, corrected, bias_note);
  if (times != nullptr) times->range_bias_s = secondsSince(start);
  start = std::chrono::steady_clock::now();
  RoomLayout layout;
  // The cloud as the fit sees it is levelled; the image is the unlevelled top camera's,
  // half the baseline above the rig's centre.
  LayoutImage image;
  image.color = top_color;
  image.camera_from_rig = Eigen::Translation3d(0.0, 0.0, -0.5 * baseline_m) * Eigen::Isometry3d(level_tilt.transpose());
  if (isIdentity(level_tilt)) {
    layout = fitRoomLayout(fitted_cloud, options.layout, &image);
  } else {
    PointCloud level = fitted_cloud;
    const Eigen::Matrix3f tilt_f = level_tilt.cast<float>();
    for (CloudPoint& point : level.points) point.p = tilt_f * point.p;
    layout = fitRoomLayout(level, options.layout, &image);
    // The fit's rig frame is the levelled one; the caller's is before the tilt.
    layout.room_from_rig = layout.room_from_rig * Eigen::Isometry3d(level_tilt);
    layout.model.rig_rotation = Eigen::Quaterniond(layout.room_from_rig.rotation()).normalized();
  }
  if (!leveled.empty()) layout.warnings.insert(layout.warnings.begin(), leveled);
  if (!bias_note.empty()) layout.warnings.push_back(bias_note);
  if (times != nullptr) times->layout_s = leveling_s + secondsSince(start);

  start = std::chrono::steady_clock::now();
  VisualRouteOptions loaded;
  if (!options.classifier || !options.families) loadDefaultMaterialModels(loaded);
  const MaterialClassifier& classifier = options.classifier ? *options.classifier : *loaded.classifier;
  const MaterialFamilyTable& families = options.families ? *options.families : *loaded.families;
  // The image is the (unlevelled) top camera's; layout.room_from_rig includes the tilt, so
  // the step's rays from the camera land where the image saw them.
  auto decisions = assignSurfaceMaterials(layout, top_color, baseline_m, classifier, families, options.materials);
  if (materials != nullptr) *materials = std::move(decisions);
  if (times != nullptr) times->materials_s = secondsSince(start);
  if (options.relief.enabled && options.layout.assign_points) {
    start = std::chrono::steady_clock::now();
    applySurfaceRelief(layout,
                       estimateSurfaceRelief(fitted_cloud, layout, layout.room_from_rig, options.layout, options.relief));
    if (times != nullptr) times->relief_s = secondsSince(start);
  }
  return layout;
}

VisualRoute runVisualRoute(const cv::Mat& top, const cv::Mat& bottom, double baseline_m,
                           const VisualRouteOptions& options, const Eigen::Matrix3d& tilt) {
  VisualRoute route;
  auto start = std::chrono::steady_clock::now();
  route.depth = computeSphericalDepth(top, bottom, baseline_m, options.stereo);
  route.times.stereo_s = secondsSince(start);
  start = std::chrono::steady_clock::now();
  route.cloud = depthToPointCloud(route.depth, top, baseline_m, options.cloud);
  route.times.cloud_s = secondsSince(start);
  route.layout = roomLayoutFromCloud(route.cloud, top, baseline_m, options, tilt, &route.times, &route.materials);
  return route;
}

}  // namespace room_reverb::core
