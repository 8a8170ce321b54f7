// The synthetic capture generator against known truth: ranges from plane geometry, ids of
// what each pixel sees, the rig's two cameras a baseline apart, determinism, noise, and the
// errors a user can cause.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <set>

#include "room_reverb/common/error.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/equirect.h"
#include "room_reverb/vision/texture_family.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;

const MaterialLibrary& library() {
  static const MaterialLibrary lib = MaterialLibrary::loadDefault();
  return lib;
}

// A 5 x 4 x 3 m room, each face a different material, the rig at (2, 1.5, 1.4).
RoomModel testRoom() {
  RoomModel room;
  room.size_m = {5.0, 4.0, 3.0};
  const char* materials[] = {"carpet", "plaster_smooth", "brick_bare", "glass_window", "wood_panel", "concrete_painted"};
  for (std::size_t f = 0; f < kRoomSurfaceNames.size(); ++f) room.surfaces[kRoomSurfaceNames[f]] = {materials[f], 1.0};
  room.rig_position_m = {2.0, 1.5, 1.4};
  return room;
}

CaptureOptions smallOptions(int width = 256) {
  CaptureOptions options;
  options.width = width;
  options.supersampling = 1;
  return options;
}

// One camera at (2, 2, 1.5), facing +x.
CameraCapture cameraAt(const RoomModel& room, const CaptureOptions& options) {
  return renderCaptureCamera(room, library(), options, {2, 2, 1.5}, Eigen::Quaterniond::Identity());
}

// The standard deviation of a noisy render against the same render without noise.
double noiseSigma(const CameraCapture& noisy, const CameraCapture& clean) {
  cv::Mat difference;
  cv::subtract(noisy.color, clean.color, difference, cv::noArray(), CV_32FC3);
  cv::Scalar mean, sigma;
  cv::meanStdDev(difference.reshape(1), mean, sigma);
  return sigma[0];
}

// Distance along a unit ray from inside the box to the plane of box face `face`
// (kRoomSurfaceNames order), or inf when the ray does not head towards it.
double distanceToFace(const Eigen::Vector3d& size, int face, const Eigen::Vector3d& origin, const Eigen::Vector3d& d) {
  const int axis = face < 2 ? 2 : (face < 4 ? 0 : 1);
  const bool high = face == 1 || face == 3 || face == 5;
  const double plane = high ? size[axis] : 0.0;
  const double t = (plane - origin[axis]) / d[axis];
  return t > 0.0 ? t : std::numeric_limits<double>::infinity();
}

}  // namespace

TEST(CaptureGenerator, RangeOfEveryBoxPixelIsTheDistanceToItsFacePlane) {
  const RoomModel room = testRoom();
  std::vector<std::string> names;
  const Eigen::Vector3d camera(2.0, 1.5, 1.4);
  const CameraCapture c = renderCaptureCamera(room, library(), smallOptions(), camera, Eigen::Quaterniond::Identity(), &names);
  ASSERT_EQ(c.range_m.type(), CV_32FC1);
  ASSERT_EQ(c.range_m.cols, 256);
  ASSERT_EQ(c.range_m.rows, 128);
  const EquirectGeometry g{256, 128};
  double worst = 0.0;
  for (int v = 0; v < g.height; ++v) {
    for (int u = 0; u < g.width; ++u) {
      const Eigen::Vector3d d = equirectPixelDirection(g, u, v);
      // The face the ray meets first is the nearest plane ahead of it.
      int face = 0;
      double nearest = std::numeric_limits<double>::infinity();
      for (int f = 0; f < 6; ++f) {
        const double t = distanceToFace(room.size_m, f, camera, d);
        if (t < nearest) nearest = t, face = f;
      }
      ASSERT_EQ(c.object_id.at<std::uint16_t>(v, u), face) << u << "," << v;
      worst = std::max(worst, std::abs(c.range_m.at<float>(v, u) - nearest));
      ASSERT_EQ(names[c.material_id.at<std::uint16_t>(v, u)], room.surfaces.at(kRoomSurfaceNames[face]).material);
    }
  }
  // Stored as float: 1e-4 m is ~50 ulps at 5 m.
  EXPECT_LT(worst, 1e-4);
}

TEST(CaptureGenerator, FloorAndCeilingRangeFollowElevation) {
  const RoomModel room = testRoom();
  const CaptureOptions options = smallOptions(512);
  const StereoCapture capture = renderCapture(room, library(), options);
  const EquirectGeometry g{512, 256};
  // Camera heights: the rig's 1.4 m +- half the 0.2 m baseline.
  for (const auto& [camera, height] : {std::pair<const CameraCapture*, double>{&capture.top, 1.5}, {&capture.bottom, 1.3}}) {
    EXPECT_NEAR(camera->position_m.z(), height, 1e-12);
    int floor_rows = 0, ceiling_rows = 0;
    for (int v = 0; v < g.height; ++v) {
      const double elevation = equirectElevation(g, v);
      const int u = g.width / 3;
      const auto id = camera->object_id.at<std::uint16_t>(v, u);
      const double range = camera->range_m.at<float>(v, u);
      if (id == 0) {
        EXPECT_NEAR(range, height / std::sin(-elevation), 1e-4) << "row " << v;
        ++floor_rows;
      } else if (id == 1) {
        EXPECT_NEAR(range, (3.0 - height) / std::sin(elevation), 1e-4) << "row " << v;
        ++ceiling_rows;
      }
    }
    EXPECT_GT(floor_rows, 40);
    EXPECT_GT(ceiling_rows, 40);
  }
}

TEST(CaptureGenerator, AYawedCuboidIsSeenAtItsNearEdge) {
  RoomModel room = testRoom();
  const Eigen::Vector3d camera(1.0, 2.0, 1.2);
  const EquirectGeometry g{512, 256};
  // A pixel just above the horizon looking roughly along +x; the cube's centre is 2 m
  // down that pixel's ray, turned so that a vertical edge faces the camera.
  const int u = g.width / 2 + 3, v = g.height / 2 - 1;
  const Eigen::Vector3d d = equirectPixelDirection(g, u, v);
  const double half = 0.3;
  CuboidObject cube;
  cube.label = "cube";
  cube.material = "wood_panel";
  cube.center_m = camera + 2.0 * d;
  cube.size_m = Eigen::Vector3d::Constant(2.0 * half);
  cube.yaw_rad = std::atan2(d.y(), d.x()) + kPi / 4.0;
  room.objects.push_back(cube);
  const CameraCapture c = renderCaptureCamera(room, library(), smallOptions(512), camera, Eigen::Quaterniond::Identity());
  EXPECT_EQ(c.object_id.at<std::uint16_t>(v, u), kCaptureFirstObjectId);
  // The edge is half a face diagonal nearer than the centre, horizontally.
  const double cos_elevation = std::hypot(d.x(), d.y());
  EXPECT_NEAR(c.range_m.at<float>(v, u), 2.0 - half * std::sqrt(2.0) / cos_elevation, 1e-4);
  // The cube's pixels are where it should be and only there: about its solid angle.
  const int pixels = cv::countNonZero(c.object_id == kCaptureFirstObjectId);
  const double pixel_solid_angle = (2 * kPi / g.width) * (kPi / g.height);
  const double approx_solid_angle = (2 * half * std::sqrt(2.0)) * (2 * half) / (2.0 * 2.0);  // silhouette / distance^2
  EXPECT_NEAR(pixels * pixel_solid_angle, approx_solid_angle, 0.25 * approx_solid_angle);
}

TEST(CaptureGenerator, EveryFaceAndObjectAppearsWithItsIdAndAnOpenTopShowsSky) {
  RoomModel room = testRoom();
  room.objects.push_back({"table", "wood_panel", {3.5, 1.0, 0.37}, {1.2, 0.8, 0.74}, 0.3, 1.0});
  room.objects.push_back({"shelf", "bookshelf_with_books", {0.3, 3.0, 1.0}, {0.4, 1.2, 2.0}, 0.0, 1.0});
  const StereoCapture closed = renderCapture(room, library(), smallOptions());
  std::set<int> ids;
  for (auto it = closed.top.object_id.begin<std::uint16_t>(); it != closed.top.object_id.end<std::uint16_t>(); ++it) ids.insert(*it);
  EXPECT_EQ(ids, (std::set<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(closed.object_names.size(), 8u);
  EXPECT_EQ(closed.object_names[6], "table");
  EXPECT_EQ(closed.material_names.size(), 7u);  // six faces and the shelf (the table repeats wood_panel)

  room.has_ceiling = false;
  const StereoCapture open = renderCapture(room, library(), smallOptions());
  // The zenith row is sky: infinite range, sky ids; the horizon is still walls.
  for (int u = 0; u < 256; u += 16) {
    EXPECT_EQ(open.top.object_id.at<std::uint16_t>(0, u), kCaptureSkyId);
    EXPECT_EQ(open.top.material_id.at<std::uint16_t>(0, u), kCaptureSkyId);
    EXPECT_TRUE(std::isinf(open.top.range_m.at<float>(0, u)));
    EXPECT_NE(open.top.object_id.at<std::uint16_t>(64, u), kCaptureSkyId);
  }
  EXPECT_EQ(std::count(open.material_names.begin(), open.material_names.end(), "plaster_smooth"), 0);
}

TEST(CaptureGenerator, TopAndBottomCamerasSeeOnePointAtTheBaselineGeometry) {
  RoomModel room = testRoom();
  room.objects.push_back({"table", "wood_panel", {3.5, 1.0, 0.37}, {1.2, 0.8, 0.74}, 0.3, 1.0});
  // A rig turned and slightly tilted, so the baseline is not the room's z.
  room.rig_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitZ()) *
                                         Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()));
  CaptureOptions options = smallOptions(512);
  options.supersampling = 2;
  const StereoCapture capture = renderCapture(room, library(), options);
  const Eigen::Matrix3d r = room.rig_rotation.toRotationMatrix();
  EXPECT_LT((capture.top.position_m - capture.bottom.position_m - r * Eigen::Vector3d(0, 0, 0.2)).norm(), 1e-12);
  EXPECT_LT((0.5 * (capture.top.position_m + capture.bottom.position_m) - room.rig_position_m).norm(), 1e-12);

  const EquirectGeometry g{512, 256};
  int checked = 0;
  std::vector<double> colour_differences;
  for (int v = 8; v < g.height - 8; v += 5) {
    for (int u = 0; u < g.width; u += 7) {
      const float range = capture.top.range_m.at<float>(v, u);
      const auto id = capture.top.object_id.at<std::uint16_t>(v, u);
      const Eigen::Vector3d point = capture.top.position_m + range * (r * equirectPixelDirection(g, u, v));
      // Where the bottom camera sees that point, and the range it measures there.
      const Eigen::Vector2d uv = equirectCoordinates(g, r.transpose() * (point - capture.bottom.position_m));
      const int u0 = static_cast<int>(std::floor(uv.x() - 0.5)), v0 = static_cast<int>(std::floor(uv.y() - 0.5));
      if (u0 < 0 || u0 + 1 >= g.width || v0 < 0 || v0 + 1 >= g.height) continue;
      bool same_surface = true;
      for (int k = 0; k < 4; ++k) same_surface = same_surface && capture.bottom.object_id.at<std::uint16_t>(v0 + k / 2, u0 + k % 2) == id;
      if (!same_surface) continue;  // an edge or an occlusion between the two views
      cv::Mat patch;
      cv::getRectSubPix(capture.bottom.range_m, cv::Size(1, 1), cv::Point2f(float(uv.x() - 0.5), float(uv.y() - 0.5)), patch);
      EXPECT_NEAR(patch.at<float>(0, 0), (point - capture.bottom.position_m).norm(), 3e-3) << u << "," << v;
      cv::getRectSubPix(capture.bottom.color, cv::Size(1, 1), cv::Point2f(float(uv.x() - 0.5), float(uv.y() - 0.5)), patch);
      const cv::Vec3b a = capture.top.color.at<cv::Vec3b>(v, u), b = patch.at<cv::Vec3b>(0, 0);
      colour_differences.push_back((std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2])) / 3.0);
      ++checked;
    }
  }
  EXPECT_GT(checked, 2000);
  // Textures live on the surfaces, so one point has one colour in both views (up to
  // resampling): what stereo matching relies on.
  std::nth_element(colour_differences.begin(), colour_differences.begin() + colour_differences.size() / 2, colour_differences.end());
  EXPECT_LT(colour_differences[colour_differences.size() / 2], 4.0);
}

TEST(CaptureGenerator, TheSameSeedGivesTheSameBytesOnAnyThreadCount) {
  RoomModel room = testRoom();
  CaptureOptions options = smallOptions();
  options.noise_sigma = 2.0;
  options.threads = 1;
  const StereoCapture a = renderCapture(room, library(), options);
  options.threads = 3;
  const StereoCapture b = renderCapture(room, library(), options);
  for (const auto& [x, y] : {std::pair{&a.top, &b.top}, {&a.bottom, &b.bottom}}) {
    EXPECT_EQ(cv::norm(x->color, y->color, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(x->range_m, y->range_m, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(x->object_id, y->object_id, cv::NORM_INF), 0.0);
  }
  options.seed = 2;
  const StereoCapture c = renderCapture(room, library(), options);
  EXPECT_GT(cv::norm(a.top.color, c.top.color, cv::NORM_L1) / a.top.color.total(), 1.0);
  EXPECT_EQ(cv::norm(a.top.range_m, c.top.range_m, cv::NORM_INF), 0.0);  // the geometry is not random
  // The two cameras' noise is independent.
  EXPECT_GT(cv::norm(a.top.color, a.bottom.color, cv::NORM_L1), 0.0);
}

TEST(CaptureGenerator, SensorNoiseHasTheRequestedSigma) {
  const RoomModel room = testRoom();
  CaptureOptions options = smallOptions();
  options.shading = false;
  const CameraCapture clean = cameraAt(room, options);
  options.noise_sigma = 6.0;
  const CameraCapture noisy = cameraAt(room, options);
  cv::Mat difference;
  cv::subtract(noisy.color, clean.color, difference, cv::noArray(), CV_32FC3);
  cv::Scalar mean, sigma;
  cv::meanStdDev(difference.reshape(1), mean, sigma);
  EXPECT_NEAR(mean[0], 0.0, 0.2);
  EXPECT_NEAR(sigma[0], 6.0, 0.3);
}

// Mean of channel `ch` over rows [r0, r1) and columns [c0, c1) of a CV_8UC3 image.
double patchMean(const cv::Mat& image, int r0, int r1, int c0, int c1, int ch) {
  return cv::mean(image(cv::Range(r0, r1), cv::Range(c0, c1)))[ch];
}

TEST(CaptureGenerator, EachCameraExposesAndWhiteBalancesOnItsOwn) {
  const RoomModel room = testRoom();
  CaptureOptions options = smallOptions();
  options.shading = false;
  const StereoCapture ideal = renderCapture(room, library(), options);
  options.camera.top_exposure = 0.5;
  options.camera.bottom_white_balance = {0.9, 1.0, 0.8};
  const StereoCapture exposed = renderCapture(room, library(), options);
  for (int ch = 0; ch < 3; ++ch) {
    // Half the light, to within the rounding of each pixel.
    EXPECT_NEAR(patchMean(exposed.top.color, 20, 108, 0, 256, ch), 0.5 * patchMean(ideal.top.color, 20, 108, 0, 256, ch), 0.6);
  }
  // BGR: blue 0.8, green 1, red 0.9 of the bottom camera's light.
  const double gains[3] = {0.8, 1.0, 0.9};
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(patchMean(exposed.bottom.color, 20, 108, 0, 256, ch), gains[ch] * patchMean(ideal.bottom.color, 20, 108, 0, 256, ch),
                0.6);
  }
}

// Through the lenses, light falls off towards each lens's rim as 1 - v (angle / 90 deg)^2
// and the back lens has its own gain: measured against the same lenses without either.
TEST(CaptureGenerator, LensesVignetteTowardsTheSeamsAndTheBackLensHasItsOwnGain) {
  const RoomModel room = testRoom();
  CaptureOptions options = smallOptions();
  options.shading = false;
  options.camera.through_lenses = true;
  const CameraCapture plain = cameraAt(room, options);
  options.camera.vignetting = 0.3;
  options.camera.back_lens_gain = 0.8;
  const CameraCapture lensed = cameraAt(room, options);
  // Columns of a 256-wide image: azimuth 0 (the front lens's axis) at 128, 180 deg (the
  // back lens's axis) at 0 and 255, the seams at 64 and 192. Rows 60-68 straddle the horizon.
  const auto ratio = [&](int c0, int c1) {
    double sum = 0.0;
    for (int ch = 0; ch < 3; ++ch) sum += patchMean(lensed.color, 60, 68, c0, c1, ch) / patchMean(plain.color, 60, 68, c0, c1, ch);
    return sum / 3.0;
  };
  EXPECT_NEAR(ratio(124, 132), 1.0, 0.01);                                      // on the front axis
  EXPECT_NEAR(ratio(0, 4), 0.8, 0.01);                                          // on the back axis
  // Column c is 180 - 360 (c + 0.5) / 256 deg off the front axis: 50 deg at 92, 67 at 80.
  EXPECT_NEAR(ratio(88, 96), 1.0 - 0.3 * std::pow(50.0 / 90.0, 2.0), 0.01);
  EXPECT_NEAR(ratio(78, 82), 1.0 - 0.3 * std::pow(67.0 / 90.0, 2.0), 0.01);
  // Without the effects, the lenses' image is the direct render resampled.
  options.camera = CameraImperfections{};
  const CameraCapture direct = cameraAt(room, options);
  EXPECT_NEAR(patchMean(plain.color, 20, 108, 0, 256, 1), patchMean(direct.color, 20, 108, 0, 256, 1), 1.0);
}

TEST(CaptureGenerator, LightsGlowPastWhiteAndJpegCostsWhatItsQualitySays) {
  RoomModel room = testRoom();
  room.objects.push_back({"light", "metal", {2.0, 1.5, 2.8}, {0.6, 0.6, 0.06}, 0.0, 1.0});
  CaptureOptions options = smallOptions();
  const CameraCapture dark = cameraAt(room, options);
  options.camera.emitter_labels = {"light"};
  const CameraCapture lit = cameraAt(room, options);
  int light_pixels = 0, white = 0, white_before = 0;
  for (int r = 0; r < lit.object_id.rows; ++r) {
    for (int c = 0; c < lit.object_id.cols; ++c) {
      if (lit.object_id.at<std::uint16_t>(r, c) != kCaptureFirstObjectId) continue;
      ++light_pixels;
      const cv::Vec3b p = lit.color.at<cv::Vec3b>(r, c), q = dark.color.at<cv::Vec3b>(r, c);
      white += p[0] >= 250 && p[1] == 255 && p[2] == 255;  // a warm white: blue at 0.9 x 400 clips too
      white_before += q[1] == 255;
    }
  }
  ASSERT_GT(light_pixels, 20);
  EXPECT_GE(white, light_pixels * 9 / 10);
  EXPECT_EQ(white_before, 0);

  const auto meanDifference = [&](int quality) {
    CaptureOptions o = smallOptions();
    o.camera.jpeg_quality = quality;
    const CameraCapture c = cameraAt(room, o);
    cv::Mat diff;
    cv::absdiff(c.color, dark.color, diff);
    return cv::mean(diff.reshape(1))[0];
  };
  const double poor = meanDifference(30), good = meanDifference(95);
  EXPECT_GT(poor, 0.5);
  EXPECT_GT(good, 0.0);
  EXPECT_LT(good, 0.6 * poor);
}

// Recorded at twice the width and shrunk: the capture's size, the same light, and the
// sensor's noise averaged over four native pixels (half its sigma).
TEST(CaptureGenerator, ACameraRecordingAtTwiceTheWidthIsShrunkToIt) {
  const RoomModel room = testRoom();
  CaptureOptions options = smallOptions();
  options.shading = false;
  options.camera.native_scale = 2;
  const CameraCapture clean = cameraAt(room, options);
  ASSERT_EQ(clean.color.size(), cv::Size(256, 128));
  ASSERT_EQ(clean.range_m.size(), cv::Size(256, 128));
  CaptureOptions native = options;
  native.camera.native_scale = 1;
  const CameraCapture direct = cameraAt(room, native);
  EXPECT_NEAR(patchMean(clean.color, 20, 108, 0, 256, 1), patchMean(direct.color, 20, 108, 0, 256, 1), 1.0);
  options.noise_sigma = 6.0;
  EXPECT_NEAR(noiseSigma(cameraAt(room, options), clean), 3.0, 0.3);
}

TEST(CaptureGenerator, APoorlyTexturedMaterialIsNearlyFlat) {
  const RoomModel room = testRoom();
  CaptureOptions options = smallOptions();
  options.shading = false;
  auto wallSpread = [&](const CaptureOptions& o) {
    std::vector<std::string> names;
    const CameraCapture c = renderCaptureCamera(room, library(), o, {2, 2, 1.5}, Eigen::Quaterniond::Identity(), &names);
    cv::Mat grey;
    cv::cvtColor(c.color, grey, cv::COLOR_BGR2GRAY);
    cv::Scalar mean, sigma;
    cv::meanStdDev(grey, mean, sigma, c.object_id == 5);  // wall_y_max, concrete_painted
    return sigma[0];
  };
  const double normal = wallSpread(options);
  options.low_texture_materials = {"concrete_painted"};
  const double flat = wallSpread(options);
  EXPECT_GT(normal, 4.0);
  EXPECT_LT(flat, 0.1 * normal);
}

TEST(CaptureGenerator, SupersamplingSmoothsEdges) {
  const RoomModel room = testRoom();
  CaptureOptions options = smallOptions();
  options.shading = false;
  auto roughness = [&](int n) {
    options.supersampling = n;
    const CameraCapture c = cameraAt(room, options);
    cv::Mat laplacian;
    cv::Laplacian(c.color, laplacian, CV_32F);
    return cv::norm(laplacian, cv::NORM_L1);
  };
  EXPECT_LT(roughness(3), roughness(1));
}

TEST(CaptureGenerator, EveryLibraryMaterialHasATextureFamily) {
  std::set<TextureFamily> used;
  for (const std::string& name : library().names()) {
    const TextureFamilyChoice choice = textureFamilyFor(name);
    EXPECT_NE(choice.source, TextureFamilySource::kDefault) << name << " has no row in the family table";
    used.insert(choice.family);
  }
  EXPECT_EQ(used.size(), allTextureFamilies().size());
  EXPECT_EQ(textureFamilyFor("my_oak_boards").family, TextureFamily::kWood);
  EXPECT_EQ(textureFamilyFor("Glass_Wool_Panel").family, TextureFamily::kFoam);
  EXPECT_EQ(textureFamilyFor("mystery").source, TextureFamilySource::kDefault);
}

TEST(CaptureGenerator, FamiliesHaveDistinctColours) {
  // One room per family, flat lit: the mean colour of the floor.
  std::vector<cv::Scalar> means;
  const char* examples[] = {"plaster_smooth", "brick_bare", "wood_floor", "carpet", "tiles_ceramic", "glass_window",
                            "curtain_heavy", "concrete_unpainted", "metal", "acoustic_foam", "grass", "open_window"};
  CaptureOptions options = smallOptions(128);
  options.shading = false;
  for (const char* material : examples) {
    RoomModel room = testRoom();
    room.surfaces["floor"].material = material;
    const CameraCapture c = cameraAt(room, options);
    means.push_back(cv::mean(c.color, c.object_id == 0));
  }
  for (std::size_t i = 0; i < means.size(); ++i) {
    for (std::size_t j = i + 1; j < means.size(); ++j) {
      EXPECT_GT(cv::norm(means[i] - means[j]), 15.0) << examples[i] << " vs " << examples[j];
    }
  }
}

TEST(CaptureGenerator, BadInputsAreInputErrors) {
  const RoomModel room = testRoom();
  auto render = [&](const RoomModel& r, const CaptureOptions& o) { return [r, o] { renderCapture(r, library(), o); }; };
  CaptureOptions options = smallOptions();
  options.width = 257;
  expectInputError(render(room, options), {"width 257", "even"});
  options.width = 62;
  expectInputError(render(room, options), {"width 62", "at least 64"});
  options = smallOptions();
  options.baseline_m = 0.0;
  expectInputError(render(room, options), {"baseline_m 0", "positive"});
  options.baseline_m = -0.2;
  expectInputError(render(room, options), {"baseline_m -0.2"});
  options = smallOptions();
  options.low_texture_materials = {"plastr"};
  expectInputError(render(room, options), {"capture.low_texture_materials", "unknown material 'plastr'"});

  RoomModel high = testRoom();
  high.rig_position_m.z() = 2.95;  // the top camera would be at 3.05 m in a 3 m room
  expectInputError(render(high, smallOptions()), {"top camera", "outside the room box", "[2, 1.5, 3.05]"});
  RoomModel outside = testRoom();
  outside.rig_position_m.x() = -1.0;
  expectInputError(render(outside, smallOptions()), {"outside the room box"});
  RoomModel blocked = testRoom();
  blocked.objects.push_back({"pillar", "concrete", {2.0, 1.5, 1.5}, {0.5, 0.5, 3.0}, 0.0, 1.0});
  expectInputError(render(blocked, smallOptions()), {"inside objects[0] (pillar)"});
  RoomModel unknown = testRoom();
  unknown.surfaces["floor"].material = "carpt";
  expectInputError(render(unknown, smallOptions()), {"surfaces.floor.material", "unknown material 'carpt'"});
  RoomModel flat = testRoom();
  flat.size_m.z() = 0.0;
  expectInputError(render(flat, smallOptions()), {"size_m"});

  const auto camera = [&](auto change) {
    CaptureOptions o = smallOptions();
    change(o.camera);
    return render(room, o);
  };
  expectInputError(camera([](CameraImperfections& c) { c.vignetting = 1.0; }), {"camera.vignetting 1", "[0, 1)"});
  expectInputError(camera([](CameraImperfections& c) { c.lens_offset_m = 0.2; }), {"camera.lens_offset_m 0.2"});
  expectInputError(camera([](CameraImperfections& c) { c.bottom_exposure = 0.0; }), {"camera.bottom_exposure 0", "positive"});
  expectInputError(camera([](CameraImperfections& c) { c.bottom_white_balance.y() = -1.0; }), {"camera.bottom_white_balance -1"});
  expectInputError(camera([](CameraImperfections& c) { c.jpeg_quality = 101; }), {"camera.jpeg_quality 101", "1 to 100"});
  expectInputError(camera([](CameraImperfections& c) { c.native_scale = 0; }), {"camera.native_scale 0", "1 to 4"});
  expectInputError(camera([](CameraImperfections& c) { c.emitter_grey = std::nan(""); }), {"camera.emitter_grey"});
}

TEST(CaptureScene, ReadsTheCaptureSectionAndWritesItBack) {
  const std::string text = std::string(R"(room_box: {size_m: [4, 3, 2.5]}
surfaces:
  floor: {material: carpet}
  ceiling: {material: plaster_smooth}
  wall_x_min: {material: brick_bare}
  wall_x_max: {material: plaster_smooth}
  wall_y_min: {material: plaster_smooth}
  wall_y_max: {material: sheetrock}
rig_in_room: {position_m: [1, 1, 1.2], rotation_xyzw: [0, 0, 0, 1]}
capture: {baseline_m: 0.25, width: 512, seed: 7, shading: false, noise_sigma: 1.5, low_texture_materials: [sheetrock]}
)");
  const CaptureScene scene = parseCaptureScene(text);
  EXPECT_EQ(scene.options.baseline_m, 0.25);
  EXPECT_EQ(scene.options.width, 512);
  EXPECT_EQ(scene.options.seed, 7u);
  EXPECT_FALSE(scene.options.shading);
  EXPECT_EQ(scene.options.noise_sigma, 1.5);
  EXPECT_EQ(scene.options.low_texture_materials, std::vector<std::string>{"sheetrock"});
  const CaptureScene again = parseCaptureScene(captureSceneToYaml(scene));
  EXPECT_EQ(again.options.baseline_m, 0.25);
  EXPECT_EQ(again.options.seed, 7u);
  EXPECT_EQ(again.options.low_texture_materials, scene.options.low_texture_materials);
  EXPECT_EQ(again.room.rig_position_m, scene.room.rig_position_m);

  const std::string with_camera = text.substr(0, text.find("capture:")) +
                                  "capture: {camera: {through_lenses: true, vignetting: 0.25, bottom_white_balance: [1.1, 1, 0.9], "
                                  "jpeg_quality: 80, emitter_labels: [light, window]}}\n";
  const CaptureScene camera = parseCaptureScene(with_camera);
  EXPECT_TRUE(camera.options.camera.through_lenses);
  EXPECT_EQ(camera.options.camera.vignetting, 0.25);
  EXPECT_EQ(camera.options.camera.bottom_white_balance, Eigen::Vector3d(1.1, 1.0, 0.9));
  const CaptureScene camera_again = parseCaptureScene(captureSceneToYaml(camera));
  EXPECT_EQ(camera_again.options.camera.jpeg_quality, 80);
  EXPECT_EQ(camera_again.options.camera.emitter_labels, (std::vector<std::string>{"light", "window"}));
  EXPECT_EQ(camera_again.options.camera.bottom_white_balance, camera.options.camera.bottom_white_balance);
  EXPECT_EQ(captureSceneToYaml(scene).find("camera:"), std::string::npos);  // an ideal camera writes no section
  expectInputError([&] { parseCaptureScene(text.substr(0, text.find("capture:")) + "capture: {camera: {jpeg: 80}}\n"); },
                   {"capture.camera.jpeg", "unknown key"});
  expectInputError([&] { parseCaptureScene(text.substr(0, text.find("capture:")) + "capture: {camera: {jpeg_quality: 80.5}}\n"); },
                   {"capture.camera.jpeg_quality", "whole number"});

  const std::string misspelt = text.substr(0, text.find("capture:")) + "capture: {baseline: 0.2}\n";
  expectInputError([&] { parseCaptureScene(misspelt); }, {"capture.baseline", "unknown key"});
  expectInputError([] { loadCaptureScene("/nonexistent/scene.yaml"); }, {"/nonexistent/scene.yaml", "no such file"});
}

TEST(CaptureScene, ShippedScenesAreValidAndMatchThePaperRooms) {
  const std::string dir = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    const CaptureScene scene = loadCaptureScene(entry.path().string());
    EXPECT_NO_THROW(validateCapture(scene.room, library(), scene.options)) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 5);
  const CaptureScene mr = loadCaptureScene(dir + "mr.yaml");
  EXPECT_EQ(mr.room.size_m, Eigen::Vector3d(5.61, 4.28, 2.33));
  EXPECT_EQ(mr.room.rig_position_m, Eigen::Vector3d(0.33, 2.12, 1.00));
  const CaptureScene kt = loadCaptureScene(dir + "kt.yaml");
  EXPECT_EQ(kt.room.size_m, Eigen::Vector3d(6.64, 3.46, 2.67));
  // The paper's (1.59, 4.10) is outside the room; read with x and y swapped.
  EXPECT_EQ(kt.room.rig_position_m, Eigen::Vector3d(4.10, 1.59, 1.71));
}
