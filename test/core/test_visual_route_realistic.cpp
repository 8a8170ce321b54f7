// The whole visual route as `room_reverb room-model` runs it (levelling by the images,
// pair -> depth -> cloud -> cuboids -> materials) with its default options and the shipped
// classifier, on cluttered rooms (synthetic_capture/
// cluttered_rooms.h) photographed by the capture generator with photographs of real
// surfaces from a collection the shipped classifier was not trained on, sensor noise and
// shading. Scored against the room's truth: the box of its main walls per dimension, and
// the share of the box's area (floor, ceiling, walls) whose material is of the right
// texture family. The held-out rooms' seeds from 201 on are used nowhere else; the test
// suite runs 201-202 through an ideal camera and 251-252 through a consumer one.
// The report over many rooms:
//   ROOM_REVERB_REALISTIC_ROOMS=20 [ROOM_REVERB_FIRST_ROOM=201] [ROOM_REVERB_PHOTO_SOURCE=sweethome3d]
//   [ROOM_REVERB_CAPTURE_WIDTH=2048] [ROOM_REVERB_ROOM_SET=development|development_large]
//   [ROOM_REVERB_MIN_CONFIDENCE=0.35] (the material fallback's threshold)
//   [ROOM_REVERB_CAMERA=consumer] (consumerCamera: lenses, seams, exposure, JPEG, lights, the
//   cameras' turns on the bar; ROOM_REVERB_CAMERA_WITHOUT=... turns effects off)
//   [ROOM_REVERB_PRINT_RECTIFICATION=1] (the bottom camera's turn found against the truth)
//   [ROOM_REVERB_SAVE_PAIRS=DIR] (each room's two images as DIR/roomN_top.png, _bottom.png)
//   [ROOM_REVERB_STEREO_STATS=1] (the stereo's range error by surface)
//   [ROOM_REVERB_PRINT_FACES=1] (where each face of the box lies against the truth)
//   [ROOM_REVERB_PRINT_OBJECTS=1] (the fitted objects: label, centre, size, yaw, material)
//   [ROOM_REVERB_PRINT_RELIEF=1] (each face's and object's relief: seen share off its plane,
//   scattering at 1 kHz)
//   [ROOM_REVERB_ROUTE_WITHOUT=exposure,noise,subpixel,planes,texture,junctions,joints,patch_cap,range_bias,
//   rectification,view_cap] (routeOptions, ingestOptions)
//   [ROOM_REVERB_SENSOR_NOISE=2] (the cameras' noise, grey levels at the capture's width)
//   .ws/devel/lib/room_reverb/test_visual_route_realistic --gtest_filter='*Report*'
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "room_reverb/common/error.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/synthetic_capture/cluttered_rooms.h"
#include "room_reverb/synthetic_capture/photo_textures.h"
#include "room_reverb/vision/capture_ingest.h"
#include "room_reverb/vision/material_families.h"
#include "room_reverb/vision/visual_route.h"

using namespace room_reverb::core;

namespace {

constexpr double kBaseline = 0.2;
constexpr double kPi = 3.14159265358979323846;

struct RouteScore {
  bool refused = false;
  std::string refusal;
  Eigen::Vector3d error_pct = Eigen::Vector3d::Zero();  // (fitted - true) / true size
  std::array<double, 6> face_error_m{};                  // each truth face's fitted place, outwards positive
  std::array<std::string, 6> face_basis{};               // what the fitted face at each truth face rests on
  double yaw_error_deg = 0.0;                            // the fitted walls' turn against the true ones
  double material_area_share = 0.0;                      // box area in the right family
  std::string confusions;                                // "truth->fitted" of wrong faces
  std::vector<std::string> warnings;                     // the levelling's and the layout's
  std::string stereo;                                    // ROOM_REVERB_STEREO_STATS=1: the stereo's figures by surface
  std::vector<CuboidObject> objects;                     // as fitted, room frame
  std::array<ReliefEstimate, 6> face_relief{};           // as the route estimated them
  std::vector<ReliefEstimate> object_relief;
};

// The stereo alone on the pair as rendered (no levelling): per floor, ceiling and walls,
// the share of their pixels outside the polar caps with a range, the median range error
// against the truth (its bias) and the median and 90th percentile of its size.
const VisualRouteOptions& routeOptions();

std::string stereoStats(const StereoCapture& pair) {
  const SphericalStereoOptions& options = routeOptions().stereo;
  const SphericalDepth depth = computeSphericalDepth(pair.top.color, pair.bottom.color, kBaseline, options);
  const int h = depth.range_m.rows;
  const int cap = static_cast<int>(std::ceil(options.polar_cap_deg / 180.0 * h));
  std::vector<double> errors[3];
  int pixels[3] = {0, 0, 0};
  for (int r = cap; r < h - cap; ++r) {
    for (int c = 0; c < depth.range_m.cols; ++c) {
      const std::uint16_t id = pair.top.object_id.at<std::uint16_t>(r, c);
      if (id >= kCaptureFirstObjectId) continue;
      const int k = id == 0 ? 0 : id == 1 ? 1 : 2;
      ++pixels[k];
      const float got = depth.range_m.at<float>(r, c), want = pair.top.range_m.at<float>(r, c);
      if (std::isfinite(got) && std::isfinite(want)) errors[k].push_back(100.0 * (got - want) / want);
    }
  }
  std::string out;
  // The walls' bias by true range.
  {
    const double edges[] = {0.0, 1.5, 2.5, 4.0, 6.0, 1e9};
    std::vector<double> by_range[5];
    for (int r = cap; r < h - cap; ++r) {
      for (int c = 0; c < depth.range_m.cols; ++c) {
        const std::uint16_t id = pair.top.object_id.at<std::uint16_t>(r, c);
        if (id < 2 || id >= kCaptureFirstObjectId) continue;
        const float got = depth.range_m.at<float>(r, c), want = pair.top.range_m.at<float>(r, c);
        if (!std::isfinite(got) || !std::isfinite(want)) continue;
        for (int k = 0; k < 5; ++k) {
          if (want >= edges[k] && want < edges[k + 1]) by_range[k].push_back(100.0 * (got - want) / want);
        }
      }
    }
    out += "walls' bias by range:";
    for (int k = 0; k < 5; ++k) {
      std::vector<double>& e = by_range[k];
      if (e.size() < 100) continue;
      std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
      char part[64];
      std::snprintf(part, sizeof part, " %.1f-%.1f m %+.2f %%", edges[k], std::min(edges[k + 1], 99.0), e[e.size() / 2]);
      out += part;
    }
    out += "; ";
  }
  const char* names[3] = {"floor", "ceiling", "walls"};
  for (int k = 0; k < 3; ++k) {
    std::vector<double>& e = errors[k];
    std::sort(e.begin(), e.end());
    const double bias = e.empty() ? 0.0 : e[e.size() / 2];
    for (double& v : e) v = std::abs(v);
    std::sort(e.begin(), e.end());
    char line[160];
    std::snprintf(line, sizeof line, "%s%s valid %.0f %% error median %+.2f %%, |error| median %.2f %% p90 %.2f %%",
                  k == 0 ? "" : "; ", names[k], pixels[k] > 0 ? 100.0 * e.size() / pixels[k] : 0.0, bias,
                  e.empty() ? 0.0 : e[e.size() / 2], e.empty() ? 0.0 : e[e.size() * 9 / 10]);
    out += line;
  }
  return out;
}

// The default options; ROOM_REVERB_MIN_CONFIDENCE replaces the material fallback's
// threshold (config/material_families.yaml), to measure it.
const VisualRouteOptions& routeOptions() {
  static const VisualRouteOptions options = [] {
    VisualRouteOptions o;
    loadDefaultMaterialModels(o);
    // ROOM_REVERB_ROUTE_WITHOUT=exposure,noise,subpixel,planes,texture,junctions,joints,patch_cap,range_bias:
    // the stereo without matching the cameras' exposures, without its sub-pixel refinement,
    // without the tiles' planes or keeping the matches the noise drowns, the layout without
    // its noisier retries or the ceiling's junctions in the image, the materials without the
    // tiles' joints or with every patch of a face, without the correction of the stereo's
    // disparity offset, to measure what each gives.
    const char* without_env = std::getenv("ROOM_REVERB_ROUTE_WITHOUT");
    const std::string without = without_env != nullptr ? without_env : "";
    if (without.find("exposure") != std::string::npos) o.stereo.match_exposure = false;
    if (without.find("noise") != std::string::npos) o.layout.noise_fraction_retries.clear();
    if (without.find("subpixel") != std::string::npos) o.stereo.subpixel_refinement = false;
    if (without.find("planes") != std::string::npos) o.stereo.planar_refinement = false;
    if (without.find("texture") != std::string::npos) o.stereo.min_texture_snr = 0.0;
    if (without.find("junctions") != std::string::npos) o.layout.wall_ceiling_junctions = false;
    if (without.find("joints") != std::string::npos) o.materials.tile_joints = false;
    if (without.find("patch_cap") != std::string::npos) o.materials.max_patches_per_face = 0;
    if (without.find("range_bias") != std::string::npos) o.disparity_offset.enabled = false;
    const char* threshold = std::getenv("ROOM_REVERB_MIN_CONFIDENCE");
    if (threshold != nullptr && *threshold != '\0') {
      auto families = std::make_shared<MaterialFamilyTable>(*o.families);
      families->fallback.min_confidence = std::atof(threshold);
      o.families = families;
    }
    return o;
  }();
  return options;
}

double faceArea(const Eigen::Vector3d& size, std::size_t k) {
  if (k < 2) return size.x() * size.y();
  return (k < 4 ? size.y() : size.x()) * size.z();
}

Eigen::Vector3d outwardNormal(std::size_t k) {
  static const Eigen::Vector3d normals[6] = {-Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitX(),
                                             Eigen::Vector3d::UnitX(),  -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitY()};
  return normals[k];
}

// The fitted face that is truth face k: the one whose outward normal, carried into the
// truth's room frame, points the same way (a fit may put the room frame's origin at any
// corner).
std::size_t fittedFace(const Eigen::Matrix3d& truth_from_fit, std::size_t k) {
  std::size_t best = k;
  double best_dot = -2.0;
  for (std::size_t j = 0; j < 6; ++j) {
    const double dot = (truth_from_fit * outwardNormal(j)).dot(outwardNormal(k));
    if (dot > best_dot) best_dot = dot, best = j;
  }
  return best;
}

double unitFraction(std::uint64_t& state) {
  state = state * 6364136223846793005ULL + 1442695040888963407ULL;
  return static_cast<double>(state >> 11) * 0x1.0p-53;
}
double between(std::uint64_t& state, double lo, double hi) { return lo + (hi - lo) * unitFraction(state); }

// A consumer dual-fisheye camera pair as a user's capture has it, drawn for room `index`:
// colour through two lenses 2 cm apart with 15-40 % vignetting and up to 7 % between them,
// each camera on its own auto-exposure (the bottom within a third of a stop of the top)
// and white balance (8 % per channel), recorded at twice the capture's width with JPEG at
// quality 70-95 and shrunk (a 4K live stream shrunk to 2048 px is 1.9 times; a Theta still
// is 2.6-3.3 times), ceiling panels and windows glowing past white, and the two cameras
// standing a little turned against each other on the bar.
CameraImperfections consumerCamera(int index) {
  std::uint64_t state = 0x9e3779b97f4a7c15ULL ^ static_cast<std::uint64_t>(index);
  CameraImperfections c;
  c.through_lenses = true;
  c.lens_offset_m = 0.01;
  c.vignetting = between(state, 0.15, 0.4);
  c.back_lens_gain = between(state, 0.93, 1.07);
  c.top_exposure = between(state, 0.85, 1.15);
  c.bottom_exposure = c.top_exposure * std::pow(2.0, between(state, -1.0 / 3.0, 1.0 / 3.0));
  for (int i = 0; i < 3; ++i) c.bottom_white_balance[i] = between(state, 0.92, 1.08);
  c.jpeg_quality = static_cast<int>(between(state, 70.0, 95.0));
  c.native_scale = 2;
  c.emitter_labels = {"light", "window"};
  // ROOM_REVERB_CAMERA_WITHOUT=lenses,offset,vignetting,exposure,jpeg,native,lights,mount,lean turns effects off, to
  // measure what each costs.
  const char* without_env = std::getenv("ROOM_REVERB_CAMERA_WITHOUT");
  const std::string without = without_env != nullptr ? without_env : "";
  const auto off = [&](const char* name) { return without.find(name) != std::string::npos; };
  const CameraImperfections ideal;
  if (off("lenses")) c.through_lenses = false, c.lens_offset_m = 0.0;
  if (off("offset")) c.lens_offset_m = 0.0;
  if (off("vignetting")) c.vignetting = 0.0, c.back_lens_gain = 1.0;
  if (off("exposure")) c.top_exposure = c.bottom_exposure = 1.0, c.bottom_white_balance = ideal.bottom_white_balance;
  if (off("jpeg")) c.jpeg_quality = 0;
  if (off("native")) c.native_scale = 1;
  if (off("lights")) c.emitter_labels.clear();
  // The two cameras as screwed to the bar: the bottom one turned against the top one by up
  // to a degree about each axis, the bar leaning up to half a degree off the top camera's
  // pole.
  for (int i = 0; i < 3; ++i) c.bottom_turn_deg[i] = between(state, -1.0, 1.0);
  for (int i = 0; i < 2; ++i) c.top_turn_deg[i] = between(state, -0.5, 0.5);
  if (off("mount")) c.bottom_turn_deg.setZero(), c.top_turn_deg.setZero();
  if (off("lean")) c.top_turn_deg.setZero();
  return c;
}

// As `room_reverb room-model` ingests a pair; ROOM_REVERB_ROUTE_WITHOUT=rectification takes
// the pair as it comes, view_cap levels by line segments in views of the panorama's full
// resolution.
CaptureIngestOptions ingestOptions() {
  CaptureIngestOptions o;
  const std::string without = std::getenv("ROOM_REVERB_ROUTE_WITHOUT") ? std::getenv("ROOM_REVERB_ROUTE_WITHOUT") : "";
  if (without.find("rectification") != std::string::npos) o.rectification.enabled = false;
  if (without.find("view_cap") != std::string::npos) o.manhattan.max_view_size_px = 0;
  return o;
}

RouteScore scoreRoom(const ClutteredRoom& room, int index, const std::string& photo_source, int width, bool consumer_camera = false) {
  static const PhotoTextureSet all = loadPhotoTextures(defaultPhotoTexturePath());
  CaptureOptions capture;
  capture.width = width;
  capture.supersampling = 2;
  capture.seed = 1000 + static_cast<std::uint64_t>(index);
  const char* noise_env = std::getenv("ROOM_REVERB_SENSOR_NOISE");
  capture.noise_sigma = noise_env != nullptr ? std::atof(noise_env) : 2.0;
  capture.baseline_m = kBaseline;
  capture.photo_textures = std::make_shared<const PhotoTextureSet>(all.onlySources({photo_source}));
  RoomModel scanned = room.scanned;
  if (consumer_camera) {
    capture.camera = consumerCamera(index);
    scanned.objects.insert(scanned.objects.end(), room.window_panes.begin(), room.window_panes.end());
  }
  const StereoCapture pair = renderCapture(scanned, MaterialLibrary::loadDefault(), capture);
  if (const char* dir = std::getenv("ROOM_REVERB_SAVE_PAIRS"); dir != nullptr && *dir != '\0') {
    cv::imwrite(std::string(dir) + "/room" + std::to_string(index) + "_top.png", pair.top.color);
    cv::imwrite(std::string(dir) + "/room" + std::to_string(index) + "_bottom.png", pair.bottom.color);
  }
  RouteScore score;
  if (const char* stats = std::getenv("ROOM_REVERB_STEREO_STATS"); stats != nullptr && *stats == '1') {
    score.stereo = stereoStats(pair);
  }
  VisualRoute route;
  Eigen::Matrix3d image_rotation = Eigen::Matrix3d::Identity();
  try {
    // As `room_reverb room-model` runs it: the pair levelled by its images first.
    const IngestedCapture ingested = ingestCapture(pair.top.color, pair.bottom.color, ingestOptions());
    if (const char* print = std::getenv("ROOM_REVERB_PRINT_RECTIFICATION"); print != nullptr && *print == '1') {
      const Eigen::Vector3d truth = capture.camera.bottom_turn_deg * kPi / 180.0;
      const Eigen::Matrix3d true_turn =
          truth.norm() > 0.0 ? Eigen::AngleAxisd(truth.norm(), truth.normalized()).toRotationMatrix()
                             : Eigen::Matrix3d::Identity();
      const PairRectification& r = ingested.rectification;
      std::printf("             pair: turn %.2f mrad (truth %.2f), off by %.2f mrad, %d of %d matches%s\n",
                  1e3 * r.turn_rad, 1e3 * truth.norm(),
                  1e3 * Eigen::AngleAxisd(r.bottom_to_top.transpose() * true_turn).angle(), r.inliers, r.matches,
                  r.applied ? ", rectified" : "");
    }
    image_rotation = ingested.leveling.image_rotation;
    VisualRouteOptions options = routeOptions();
    options.level_from_cloud = ingested.level_from_cloud;
    // The steps of runVisualRoute, with ROOM_REVERB_DISPARITY_OFFSET_PX bending the
    // stereo's ranges as a disparity offset of that many pixels would (range_bias.h).
    route.depth = computeSphericalDepth(ingested.top, ingested.bottom, kBaseline, options.stereo);
    route.cloud = depthToPointCloud(route.depth, ingested.top, kBaseline, options.cloud);
    if (const char* px = std::getenv("ROOM_REVERB_DISPARITY_OFFSET_PX"); px != nullptr && std::atof(px) != 0.0) {
      route.cloud = removeDisparityOffset(route.cloud, kBaseline, -std::atof(px) * kPi / ingested.top.rows);
    }
    route.layout = roomLayoutFromCloud(route.cloud, ingested.top, kBaseline, options, ingested.leveling.tilt,
                                       &route.times, &route.materials);
    if (const char* bias = std::getenv("ROOM_REVERB_PRINT_RANGE_BIAS"); bias != nullptr && *bias == '1') {
      const DisparityOffset found = estimateDisparityOffset(route.cloud, kBaseline, ingested.leveling.tilt);
      std::printf("             disparity offset %+.2f mrad (floor %+.2f, ceiling %+.2f)%s, with the azimuth "
                  "(%+.2f, %+.2f) mrad%s, planes' tilt %.2f mrad\n",
                  1e3 * found.offset_rad, 1e3 * found.floor_offset_rad, 1e3 * found.ceiling_offset_rad,
                  found.applied ? " applied" : "", 1e3 * found.cos_rad, 1e3 * found.sin_rad,
                  found.azimuth_applied ? " applied" : "", 1e3 * found.plane_tilt_rad);
    }
    score.warnings = ingested.warnings;
  } catch (const InputError& e) {
    score.refused = true;
    score.refusal = e.what();
    return score;
  }
  const RoomModel& fitted = route.layout.model;
  score.objects = fitted.objects;
  score.face_relief = route.layout.face_relief;
  score.object_relief = route.layout.object_relief;
  score.warnings.insert(score.warnings.end(), route.layout.warnings.begin(), route.layout.warnings.end());
  // The fit's rig frame is the top camera's (the rig's turned by the camera's own turn on
  // the bar) turned by the levelling's image rotation.
  const Eigen::Matrix3d top_on_bar = scanned.rig_rotation.toRotationMatrix().transpose() * pair.top.rotation.toRotationMatrix();
  const Eigen::Matrix3d truth_from_fit = room.truth.rig_rotation.toRotationMatrix() * top_on_bar *
                                         image_rotation.transpose() * route.layout.room_from_rig.linear().transpose();
  // The box's own sizes, each against the truth's axis nearest to it (a fit may swap x and
  // y); its turn against the truth is the yaw error, not a change of size.
  Eigen::Vector3d fitted_size = Eigen::Vector3d::Zero();
  for (int j = 0; j < 3; ++j) {
    int i = 0;
    truth_from_fit.col(j).cwiseAbs().maxCoeff(&i);
    fitted_size[i] = fitted.size_m[j];
  }
  score.error_pct = 100.0 * (fitted_size - room.truth.size_m).cwiseQuotient(room.truth.size_m);
  const Eigen::Vector3d fitted_x = truth_from_fit.col(0);
  score.yaw_error_deg = std::remainder(std::atan2(fitted_x.y(), fitted_x.x()), 0.5 * kPi) * 180.0 / kPi;
  // The fitted box in the truth's room frame, through the rig both share.
  const auto toTruth = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(room.truth.rig_position_m + truth_from_fit * (p - fitted.rig_position_m));
  };
  const Eigen::Vector3d a = toTruth(Eigen::Vector3d::Zero()), b = toTruth(fitted.size_m);
  const Eigen::Vector3d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  score.face_error_m = {-lo.z(), hi.z() - room.truth.size_m.z(), -lo.x(), hi.x() - room.truth.size_m.x(),
                        -lo.y(), hi.y() - room.truth.size_m.y()};
  // Each truth face's fitted face: the one whose outward normal the fit turns onto it.
  const std::array<Eigen::Vector3d, 6> outward = {-Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(),
                                                  -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitX(),
                                                  -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitY()};
  for (std::size_t k = 0; k < 6; ++k) {
    std::size_t best = 0;
    for (std::size_t j = 1; j < 6; ++j) {
      if ((truth_from_fit * outward[j]).dot(outward[k]) > (truth_from_fit * outward[best]).dot(outward[k])) best = j;
    }
    score.face_basis[k] = route.layout.face_evidence[best].basis;
  }
  double right = 0.0, total = 0.0;
  for (std::size_t k = 0; k < 6; ++k) {
    const auto truth_face = room.truth.surfaces.find(kRoomSurfaceNames[k]);
    if (truth_face == room.truth.surfaces.end()) continue;
    const auto fitted_face = fitted.surfaces.find(kRoomSurfaceNames[fittedFace(truth_from_fit, k)]);
    const double area = faceArea(room.truth.size_m, k);
    total += area;
    const TextureFamily want = textureFamilyFor(truth_face->second.material).family;
    const TextureFamily got = fitted_face == fitted.surfaces.end() ? TextureFamily::kOpening
                                                                   : textureFamilyFor(fitted_face->second.material).family;
    if (want == got) {
      right += area;
    } else {
      score.confusions += std::string(score.confusions.empty() ? "" : ", ") + kRoomSurfaceNames[k] + " " + toString(want) +
                          "->" + toString(got);
    }
  }
  score.material_area_share = total > 0.0 ? right / total : 0.0;
  return score;
}

void print(const ClutteredRoom& room, const RouteScore& s) {
  if (!s.stereo.empty()) std::printf("             stereo: %s\n", s.stereo.c_str());
  if (s.refused) {
    std::printf("[ measured ] %-14s refused: %s\n", room.name.c_str(), s.refusal.c_str());
    return;
  }
  std::printf("[ measured ] %-14s box error [%%] %+5.2f %+5.2f %+5.2f, yaw %+5.2f deg, materials right over %5.1f %% of the box%s%s\n",
              room.name.c_str(), s.error_pct.x(), s.error_pct.y(), s.error_pct.z(), s.yaw_error_deg, 100.0 * s.material_area_share,
              s.confusions.empty() ? "" : ": ", s.confusions.c_str());
  if (const char* faces = std::getenv("ROOM_REVERB_PRINT_FACES"); faces != nullptr && *faces == '1') {
    std::printf("             faces outwards [cm]:");
    for (std::size_t k = 0; k < 6; ++k) std::printf(" %s %+.1f", kRoomSurfaceNames[k], 100.0 * s.face_error_m[k]);
    std::printf("\n             faces rest on:");
    for (std::size_t k = 0; k < 6; ++k) std::printf(" %s: %s;", kRoomSurfaceNames[k], s.face_basis[k].c_str());
    std::printf("\n");
  }
  if (const char* objects = std::getenv("ROOM_REVERB_PRINT_OBJECTS"); objects != nullptr && *objects == '1') {
    for (const CuboidObject& o : room.truth.objects) {
      std::printf("             true   %-10s centre %.4f %.4f %.4f size %.4f %.4f %.4f yaw %+.5f %s\n", o.label.c_str(),
                  o.center_m.x(), o.center_m.y(), o.center_m.z(), o.size_m.x(), o.size_m.y(), o.size_m.z(), o.yaw_rad,
                  o.material.c_str());
    }
    for (const CuboidObject& o : s.objects) {
      std::printf("             object %-10s centre %.4f %.4f %.4f size %.4f %.4f %.4f yaw %+.5f %s\n", o.label.c_str(),
                  o.center_m.x(), o.center_m.y(), o.center_m.z(), o.size_m.x(), o.size_m.y(), o.size_m.z(), o.yaw_rad,
                  o.material.c_str());
    }
  }
  if (const char* relief = std::getenv("ROOM_REVERB_PRINT_RELIEF"); relief != nullptr && *relief == '1') {
    std::printf("             relief, share off the plane / s(1 kHz):");
    for (std::size_t k = 0; k < 6; ++k) {
      std::printf(" %s %.2f/%.2f", kRoomSurfaceNames[k], s.face_relief[k].relief_share, s.face_relief[k].scattering[4]);
    }
    for (std::size_t k = 0; k < s.object_relief.size() && k < s.objects.size(); ++k) {
      std::printf("; %s %.2f/%.2f", s.objects[k].label.c_str(), s.object_relief[k].relief_share, s.object_relief[k].scattering[4]);
    }
    std::printf("\n");
  }
  for (const std::string& w : s.warnings) std::printf("             warning: %s\n", w.c_str());
}

int envInt(const char* name, int fallback) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? std::atoi(value) : fallback;
}

}  // namespace

// Two held-out rooms at 1024 px, photographed with the Sweet Home 3D collection (which
// the shipped classifier never saw): a room, its box within 5 % (the bar for real
// captures), and most of its box in the right material family.
TEST(VisualRouteRealistic, HeldOutRoomsWithUnseenPhotographs) {
  for (const int index : {201, 202}) {
    const ClutteredRoom room = clutteredRoom(ClutterSet::kHeldOut, index);
    const RouteScore s = scoreRoom(room, index, "sweethome3d", 1024);
    print(room, s);
    ASSERT_FALSE(s.refused) << room.name << ": " << s.refusal;
    for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(s.error_pct[a]), 5.0) << room.name << " axis " << a;
    EXPECT_GE(s.material_area_share, 0.5) << room.name;
  }
}

// Two held-out rooms through a consumer camera (consumerCamera: the lenses and their
// seams, each camera exposed on its own, JPEG, glowing lights and windows): a room, its
// box within 5 % (the bar for real captures), most of it in the right material family.
// Room 251's floor of large tiles reads as wood patch by patch; its joints make it tiles
// (vision/tile_joints.h), and both rooms are right over all of their box (without the
// joints 251 is right over 74 %).
TEST(VisualRouteRealistic, HeldOutRoomsThroughAConsumerCamera) {
  double share_sum = 0.0;
  for (const int index : {251, 252}) {
    const ClutteredRoom room = clutteredRoom(ClutterSet::kHeldOut, index);
    const RouteScore s = scoreRoom(room, index, "sweethome3d", 1024, true);
    print(room, s);
    ASSERT_FALSE(s.refused) << room.name << ": " << s.refusal;
    for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(s.error_pct[a]), 5.0) << room.name << " axis " << a;
    EXPECT_GE(s.material_area_share, 0.5) << room.name;
    share_sum += s.material_area_share;
  }
  EXPECT_GE(share_sum / 2.0, 0.9);
}

TEST(VisualRouteRealistic, Report) {
  const int rooms = envInt("ROOM_REVERB_REALISTIC_ROOMS", 0);
  if (rooms < 1) GTEST_SKIP() << "set ROOM_REVERB_REALISTIC_ROOMS=N for the report over N rooms";
  const int first = envInt("ROOM_REVERB_FIRST_ROOM", 201);
  const int width = envInt("ROOM_REVERB_CAPTURE_WIDTH", 2048);
  const char* set_env = std::getenv("ROOM_REVERB_ROOM_SET");
  const bool development = set_env != nullptr && std::string(set_env) == "development";
  const bool large = set_env != nullptr && std::string(set_env) == "development_large";
  const char* source_env = std::getenv("ROOM_REVERB_PHOTO_SOURCE");
  const std::string source = source_env != nullptr && *source_env != '\0' ? source_env : "sweethome3d";
  const char* camera_env = std::getenv("ROOM_REVERB_CAMERA");
  const bool consumer = camera_env != nullptr && std::string(camera_env) == "consumer";
  int refused = 0, within1 = 0, within5 = 0, materials90 = 0;
  std::vector<double> errors, shares, yaws;
  for (int i = first; i < first + rooms; ++i) {
    const ClutteredRoom room =
        clutteredRoom(large ? ClutterSet::kDevelopmentLarge : development ? ClutterSet::kDevelopment : ClutterSet::kHeldOut, i);
    const RouteScore s = scoreRoom(room, i, source, width, consumer);
    print(room, s);
    if (s.refused) {
      ++refused;
      continue;
    }
    const double worst = s.error_pct.cwiseAbs().maxCoeff();
    errors.push_back(worst);
    shares.push_back(s.material_area_share);
    yaws.push_back(std::abs(s.yaw_error_deg));
    within1 += worst <= 1.0;
    within5 += worst <= 5.0;
    materials90 += s.material_area_share >= 0.9;
  }
  std::sort(errors.begin(), errors.end());
  std::sort(shares.begin(), shares.end());
  std::sort(yaws.begin(), yaws.end());
  double mean_share = 0.0;
  for (const double v : shares) mean_share += v / std::max<std::size_t>(shares.size(), 1);
  std::printf("[ measured ] %d %s rooms from %d, %d px, %s camera, photographs of %s: %d refused; box within 1 %%: %d, within 5 %%: %d, "
              "worst dimension median %.2f %%, max %.2f %%; yaw error median %.2f deg, max %.2f deg; materials right over "
              "the box: mean %.1f %%, median %.1f %%, min %.1f %%, rooms >= 90 %%: %d\n",
              rooms, large ? "large development" : development ? "development" : "held-out", first, width, consumer ? "consumer" : "ideal", source.c_str(), refused, within1, within5, errors.empty() ? 0.0 : errors[errors.size() / 2],
              errors.empty() ? 0.0 : errors.back(), yaws.empty() ? 0.0 : yaws[yaws.size() / 2], yaws.empty() ? 0.0 : yaws.back(),
              100.0 * mean_share, shares.empty() ? 0.0 : 100.0 * shares[shares.size() / 2],
              shares.empty() ? 0.0 : 100.0 * shares.front(), materials90);
}
