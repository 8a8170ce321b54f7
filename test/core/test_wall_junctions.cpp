// Where a wall meets the ceiling in the image (vision/wall_junctions.h), on equirect images
// of a box room drawn by casting each pixel's ray: a long room whose far wall is 7.3 m
// from the rig, seen at 1024 px, with sensor noise, the box the depth gave placing that
// wall at 6.0 m. And the room layout with the image: a cloud whose ceiling and far wall are
// unranged beyond 6 m (a plain far end) gets its far wall from the junction.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <vector>

#include "room_box_fit.h"
#include "room_reverb/vision/room_layout.h"
#include "room_reverb/vision/equirect.h"
#include "wall_junctions.h"

using namespace room_reverb::core;
using namespace room_reverb::core::layout;

namespace {

constexpr double kFarWallX = -7.3;  // the true far wall (aligned frame, the rig at the origin)
constexpr double kCameraZ = 0.1;    // the top camera above the rig's centre

AlignedBox trueBox() {
  AlignedBox box;
  box.x_lo = kFarWallX, box.x_hi = 1.5, box.y_lo = -1.8, box.y_hi = 1.8;
  box.floor_z = -1.3, box.top_z = 1.7;
  box.has_ceiling = true;
  return box;
}

// How far along direction d from `from` (inside the box) the ray leaves it, and the axis
// of the face it leaves through (the box is convex: the nearest of the three exits).
double boxExit(const AlignedBox& box, const Eigen::Vector3d& from, const Eigen::Vector3d& d, int& axis) {
  const double lo[3] = {box.x_lo, box.y_lo, box.floor_z}, hi[3] = {box.x_hi, box.y_hi, box.top_z};
  double t = 1e9;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12) continue;
    const double ta = ((d[a] > 0.0 ? hi[a] : lo[a]) - from[a]) / d[a];
    if (ta < t) t = ta, axis = a;
  }
  return t;
}

struct Drawing {
  cv::Vec3b ceiling{120, 120, 120}, wall{185, 200, 205}, floor{50, 70, 100};
  double tile_joint_spacing_m = 0.0;  // dark joints across the ceiling, parallel to the far wall
  bool picture = false;               // a black board 1.3 m wide on the far wall, its top 0.3 m under the ceiling
  double noise_grey = 2.0;
};

// The room as the top camera sees it: each pixel the colour of the face its ray meets.
cv::Mat drawRoom(const AlignedBox& box, const Drawing& look, int width = 1024) {
  const EquirectGeometry g{width, width / 2};
  cv::Mat image(g.height, g.width, CV_8UC3);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, look.noise_grey);
  const Eigen::Vector3d camera(0.0, 0.0, kCameraZ);
  for (int v = 0; v < g.height; ++v) {
    for (int u = 0; u < g.width; ++u) {
      const Eigen::Vector3d d = equirectPixelDirection(g, u, v);
      int axis = 0;
      const Eigen::Vector3d p = camera + boxExit(box, camera, d, axis) * d;
      cv::Vec3b c = axis < 2 ? look.wall : (d.z() > 0.0 ? look.ceiling : look.floor);
      if (look.picture && axis == 0 && d.x() < 0.0 && std::abs(p.y()) < 0.65 && p.z() > 0.6 && p.z() < box.top_z - 0.3) {
        c = cv::Vec3b(10, 10, 10);
      }
      if (axis == 2 && d.z() > 0.0 && look.tile_joint_spacing_m > 0.0 &&
          std::abs(std::remainder(p.x(), look.tile_joint_spacing_m)) < 0.012) {
        c = cv::Vec3b(60, 60, 60);
      }
      for (int k = 0; k < 3; ++k) image.at<cv::Vec3b>(v, u)[k] = cv::saturate_cast<uchar>(c[k] + noise(rng));
    }
  }
  return image;
}

Eigen::Isometry3d cameraFromAligned() { return Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, -kCameraZ)); }

AlignedBox boxFromDepth() {
  AlignedBox box = trueBox();
  box.x_lo = -6.0;  // where the depth's ceiling edge stopped
  return box;
}

}  // namespace

TEST(CeilingJunction, FindsAFarWallTheDepthPlacedShort) {
  const JunctionFit fit = ceilingJunction(junctionImage(drawRoom(trueBox(), Drawing{})), cameraFromAligned(), boxFromDepth(), 2, {});
  ASSERT_TRUE(fit.found);
  // One pixel at 7.3 m with the ceiling 1.6 m above the camera: 2 pi / 1024 * (7.3^2 + 1.6^2) / 1.6 = 0.22 m.
  EXPECT_NEAR(fit.pixel_m, 0.22, 0.02);
  EXPECT_NEAR(fit.position_m, kFarWallX, 0.5 * fit.pixel_m);
  EXPECT_GT(fit.contrast, 10.0);
}

TEST(CeilingJunction, TileJointsAcrossTheCeilingDoNotMoveIt) {
  Drawing look;
  look.tile_joint_spacing_m = 0.6;
  const JunctionFit fit = ceilingJunction(junctionImage(drawRoom(trueBox(), look)), cameraFromAligned(), boxFromDepth(), 2, {});
  ASSERT_TRUE(fit.found);
  EXPECT_NEAR(fit.position_m, kFarWallX, 0.5 * fit.pixel_m);
}

TEST(CeilingJunction, APictureOnTheFarWallDoesNotMoveIt) {
  Drawing look;
  look.picture = true;  // its top edge: a stronger step than the junction's, across a third of the wall
  const JunctionFit fit = ceilingJunction(junctionImage(drawRoom(trueBox(), look)), cameraFromAligned(), boxFromDepth(), 2, {});
  ASSERT_TRUE(fit.found);
  EXPECT_NEAR(fit.position_m, kFarWallX, 0.5 * fit.pixel_m);
}

TEST(CeilingJunction, NearWallsWithinACentimetre) {
  const AlignedBox box = trueBox();
  const Drawing look;
  const cv::Mat image = junctionImage(drawRoom(box, look));
  for (const int face : {3, 4, 5}) {
    const JunctionFit fit = ceilingJunction(image, cameraFromAligned(), box, face, {});
    ASSERT_TRUE(fit.found) << face;
    EXPECT_NEAR(fit.position_m, box.facePosition(face), 0.01) << face;
  }
}

TEST(CeilingJunction, NothingWhereTheCeilingLooksLikeTheWall) {
  Drawing look;
  look.ceiling = look.wall;
  const JunctionFit fit = ceilingJunction(junctionImage(drawRoom(trueBox(), look)), cameraFromAligned(), boxFromDepth(), 2, {});
  EXPECT_FALSE(fit.found);
}

TEST(CeilingJunction, NothingWithoutACeilingOrAnImage) {
  AlignedBox open = boxFromDepth();
  open.has_ceiling = false;
  const cv::Mat color = drawRoom(trueBox(), Drawing{});
  const cv::Mat image = junctionImage(color);
  EXPECT_FALSE(ceilingJunction(image, cameraFromAligned(), open, 2, {}).found);
  EXPECT_TRUE(junctionImage(cv::Mat()).empty());
  EXPECT_FALSE(ceilingJunction(junctionImage(cv::Mat()), cameraFromAligned(), boxFromDepth(), 2, {}).found);
  EXPECT_FALSE(ceilingJunction(color, cameraFromAligned(), boxFromDepth(), 2, {}).found);  // not prepared
  EXPECT_FALSE(ceilingJunction(image, cameraFromAligned(), boxFromDepth(), 1, {}).found);  // not a wall
}

namespace {

// What depth of that room gives: the first surface along each of the rig's rays (the rig
// at the origin, the polar caps left out), 0.3 % range noise, with no range on the ceiling
// and the side walls beyond x = -6 m nor on the far wall.
PointCloud rangedRoom() {
  const AlignedBox box = trueBox();
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.003);
  PointCloud cloud;
  for (double azimuth = -3.14159; azimuth < 3.14159; azimuth += 0.006) {
    for (double elevation = -1.3; elevation <= 1.3; elevation += 0.006) {
      const Eigen::Vector3d d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                              std::sin(elevation));
      int axis = 0;
      const Eigen::Vector3d p = boxExit(box, Eigen::Vector3d::Zero(), d, axis) * (1.0 + noise(rng)) * d;
      const bool far_end = p.x() < -6.0 && (axis == 1 || (axis == 2 && d.z() > 0.0));
      if ((axis == 0 && d.x() < 0.0) || far_end) continue;
      CloudPoint point;
      point.p = p.cast<float>();
      cloud.points.push_back(point);
    }
  }
  return cloud;
}

}  // namespace

TEST(CeilingJunction, TheLayoutPlacesAFarWallTheDepthDoesNotShow) {
  const PointCloud cloud = rangedRoom();
  const RoomLayout depth_only = fitRoomLayout(cloud);
  // Without the image the far wall stands where the ceiling's range ends.
  EXPECT_NEAR(depth_only.model.size_m.x(), 7.5, 0.1);

  LayoutImage image;
  image.color = drawRoom(trueBox(), Drawing{});
  image.camera_from_rig = cameraFromAligned();
  const RoomLayout with_image = fitRoomLayout(cloud, RoomLayoutOptions{}, &image);
  EXPECT_NEAR(with_image.model.size_m.x(), 8.8, 0.11);  // half a pixel of the junction
  EXPECT_NEAR(with_image.model.size_m.y(), 3.6, 0.03);
  EXPECT_EQ(with_image.face_evidence[2].basis, "where the image shows the ceiling meeting it");
  bool warned = false;
  for (const std::string& w : with_image.warnings) warned = warned || w.find("wall_x_min: placed where the image shows the ceiling meeting it") == 0;
  EXPECT_TRUE(warned);

  RoomLayoutOptions without;
  without.wall_ceiling_junctions = false;
  EXPECT_NEAR(fitRoomLayout(cloud, without, &image).model.size_m.x(), depth_only.model.size_m.x(), 1e-9);
}

namespace {

// Depth of the wall at box.x_lo, floor to ceiling, every 2 cm.
std::vector<WeightedPoint> wallPoints(const AlignedBox& box) {
  std::vector<WeightedPoint> raw;
  for (double y = box.y_lo; y <= box.y_hi; y += 0.02) {
    for (double z = box.floor_z; z < box.top_z; z += 0.02) {
      WeightedPoint point;
      point.p = Eigen::Vector3f(static_cast<float>(box.x_lo), static_cast<float>(y), static_cast<float>(z));
      point.weight = 1.0f;
      raw.push_back(point);
    }
  }
  return raw;
}

}  // namespace

TEST(CeilingJunction, ALineTheRigCannotSeeIsNotTheWall) {
  // Depth of a wall 4.9 m away; a junction found 6.6 m away lies behind it.
  AlignedBox box = trueBox();
  box.x_lo = -4.9;
  const std::vector<WeightedPoint> raw = wallPoints(box);
  EXPECT_FALSE(raysMeetJunction(raw, box, 2, -6.6, true, kCameraZ, 0.1, 0.66, {}));
  EXPECT_TRUE(raysMeetJunction(raw, box, 2, -5.0, true, kCameraZ, 0.1, 0.5, {}));  // within a tenth of it
  EXPECT_TRUE(raysMeetJunction({}, box, 2, -6.6, true, kCameraZ, 0.1, 0.66, {}));  // no depth there: nothing against it
}

TEST(CeilingJunction, ALineTheRaysPassIsNotTheWall) {
  // Depth of a wall 4.9 m away; a junction found 4.2 m away lies in front of it (the edge
  // of a light under the ceiling), and the rays under it go on to the wall.
  AlignedBox box = trueBox();
  box.x_lo = -4.9;
  const std::vector<WeightedPoint> raw = wallPoints(box);
  // The rays to the wall's upper 30 % above the camera: just under the line they would
  // meet the ceiling beyond it.
  const double band = 0.3 * (box.top_z - kCameraZ);
  EXPECT_FALSE(raysMeetJunction(raw, box, 2, -4.2, false, kCameraZ, band, 0.42, {}));
  EXPECT_TRUE(raysMeetJunction(raw, box, 2, -4.6, false, kCameraZ, band, 0.46, {}));  // within a tenth of it
  // Outwards the same rays say nothing against a line just beyond the wall they reach.
  EXPECT_TRUE(raysMeetJunction(raw, box, 2, -5.2, true, kCameraZ, 0.1, 0.52, {}));
}
