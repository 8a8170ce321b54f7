// Where a missing panel may lie (panel_extent.h): the prior size, the room's bounds, the
// points fit pairs deny (a strong reflection they lack, a direct sound the panel would
// block) and confirm, and a panel of a given size placed in the middle of what is allowed.
// Geometry: a 6 x 5 x 3 m room, an upright plane at x = 4.2 facing -x, so that in-plane u
// runs along -y and v along z.
#include <gtest/gtest.h>

#include <cmath>

#include "room_reverb/diagnosis/panel_extent.h"
#include "shoebox.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

constexpr double kC = 343.0;

struct PlaneCase {
  AcousticScene scene{shoeboxMesh({6.0, 5.0, 3.0}), uniformLibrary(0.2, 0.0)};
  PanelPlane plane;
  explicit PlaneCase(const Eigen::Vector3d& origin = {4.2, 2.5, 1.5}) {
    plane.origin = origin;
    plane.normal = {-1.0, 0.0, 0.0};
    plane.u = {0.0, -1.0, 0.0};
    plane.v = {0.0, 0.0, 1.0};
  }
  PanelBounds bounds(const std::vector<PanelWitness>& witnesses) const {
    return panelBounds(plane, {plane.origin}, witnesses, scene, kC);
  }
};

SpecularPath directPath(const MeasurementPair& pair) {
  SpecularPath direct;
  direct.order = 0;
  direct.delay_s = (pair.receiver_m - pair.source_m).norm() / kC;
  direct.arrival_direction = (pair.source_m - pair.receiver_m).normalized();
  return direct;
}

// A fit pair in front of the plane, symmetric about y = 1.7, z = 1.5: its panel reflection
// point is u = 0.8, v = 0, 12.3 dB below its direct sound (strong), 9.1 ms after it.
PanelWitness witnessAtU08() {
  PanelWitness w;
  w.pair.source_m = {2.2, 1.2, 1.5};
  w.pair.receiver_m = {2.2, 2.2, 1.5};
  w.paths = {directPath(w.pair)};
  return w;
}

// The reflection the panel would give the witness, as the measurement would show it.
RelativeReflection panelReflectionOf(const PanelWitness& w, const Eigen::Vector3d& point) {
  const Eigen::Vector3d S = w.pair.source_m, R = w.pair.receiver_m;
  const Eigen::Vector3d to = (point - R).normalized();
  RelativeReflection r;
  r.index = 1;
  r.delay_s = ((S - point).norm() + (point - R).norm() - (S - R).norm()) / kC;
  r.level_db = -12.0;
  r.azimuth_deg = std::atan2(to.y(), to.x()) * 180.0 / M_PI;
  r.elevation_deg = std::asin(to.z()) * 180.0 / M_PI;
  return r;
}

TEST(PanelExtent, WithoutWitnessesThePriorSizeBoundsAndAPanelIsCentredOnItsPoint) {
  const PlaneCase k;
  const PanelBounds b = k.bounds({});
  EXPECT_NEAR(b.allowed.u_min, -kMaxPanelHalfM, 1e-9);
  EXPECT_NEAR(b.allowed.u_max, kMaxPanelHalfM, 1e-9);
  EXPECT_NEAR(b.allowed.v_min, -kMaxPanelHalfM, 1e-9);
  EXPECT_NEAR(b.allowed.v_max, kMaxPanelHalfM, 1e-9);
  EXPECT_NEAR(b.support.width(), 0.5, 1e-9);
  const PanelExtent one = placePanel(b, 1.0);
  EXPECT_NEAR(one.u_min, -0.5, 1e-9);
  EXPECT_NEAR(one.u_max, 0.5, 1e-9);
  EXPECT_NEAR(one.v_min, -0.5, 1e-9);
  // No smaller than the support, no larger than allowed.
  EXPECT_NEAR(placePanel(b, 0.1).width(), 0.5, 1e-9);
  EXPECT_NEAR(placePanel(b, 9.0).height(), 2.0 * kMaxPanelHalfM, 1e-9);
}

TEST(PanelExtent, TheRoomStopsThePanelAndThePanelMovesAwayFromTheWall) {
  const PlaneCase k({4.2, 0.8, 1.5});  // 0.8 m from the wall at y = 0, which lies along +u
  const PanelBounds b = k.bounds({});
  // At least 5 cm clear of the wall, to within the 5 cm steps of the search.
  EXPECT_GE(b.allowed.u_max, 0.70 - 1e-9);
  EXPECT_LE(b.allowed.u_max, 0.75 + 1e-9);
  EXPECT_NEAR(b.allowed.u_min, -kMaxPanelHalfM, 1e-9);
  const PanelExtent e = placePanel(b, 1.6);
  EXPECT_NEAR(e.u_min + e.u_max, b.allowed.u_min + b.allowed.u_max, 1e-9);  // centred in what is allowed
  EXPECT_NEAR(e.width(), 1.6, 1e-9);
  // A smaller one holds its point (0.25 m round it) before it is centred.
  const PanelExtent small = placePanel(b, 1.0);
  EXPECT_NEAR(small.u_max, 0.25, 1e-9);
  EXPECT_NEAR(small.u_min, -0.75, 1e-9);
}

TEST(PanelExtent, AStrongReflectionAFitPairLacksCutsThePanelShortOfIt) {
  const PlaneCase k;
  const PanelWitness w = witnessAtU08();
  const auto point = witnessPoint(k.plane, w, kC);
  ASSERT_TRUE(point.has_value());
  EXPECT_NEAR(point->at.x(), 0.8, 1e-9);
  EXPECT_NEAR(point->at.y(), 0.0, 1e-9);
  EXPECT_FALSE(point->confirmed);
  const PanelBounds b = k.bounds({w});
  EXPECT_NEAR(b.allowed.u_max, 0.7, 1e-9);  // 0.1 m short of the denied point
  EXPECT_NEAR(b.allowed.u_min, -kMaxPanelHalfM, 1e-9);
  EXPECT_NEAR(b.allowed.height(), 2.0 * kMaxPanelHalfM, 1e-9);  // the cut that keeps the most
}

TEST(PanelExtent, AMeasuredReflectionTheModelLacksConfirmsThePanelThere) {
  const PlaneCase k;
  PanelWitness w = witnessAtU08();
  const Eigen::Vector3d on_plane(4.2, 1.7, 1.5);
  w.reflections = {panelReflectionOf(w, on_plane)};
  const auto point = witnessPoint(k.plane, w, kC);
  ASSERT_TRUE(point.has_value());
  EXPECT_TRUE(point->confirmed);
  const PanelBounds b = k.bounds({w});
  EXPECT_NEAR(b.support.u_max, 1.05, 1e-9);
  EXPECT_NEAR(b.allowed.u_max, kMaxPanelHalfM, 1e-9);
  // When a model path already explains that reflection, it says nothing either way.
  SpecularPath wall = w.paths.front();
  wall.order = 1;
  wall.delay_s += w.reflections.front().delay_s;
  wall.arrival_direction = (on_plane - w.pair.receiver_m).normalized();
  w.paths.push_back(wall);
  EXPECT_FALSE(witnessPoint(k.plane, w, kC).has_value());
  EXPECT_NEAR(k.bounds({w}).allowed.u_max, kMaxPanelHalfM, 1e-9);
}

TEST(PanelExtent, APanelMayNotBlockAFitPairsDirectSound) {
  const PlaneCase k;
  PanelWitness w;
  w.pair.source_m = {3.0, 2.0, 1.5};
  w.pair.receiver_m = {5.0, 2.0, 1.5};  // behind the plane
  const auto point = witnessPoint(k.plane, w, kC);
  ASSERT_TRUE(point.has_value());
  EXPECT_NEAR(point->at.x(), 0.5, 1e-9);
  EXPECT_FALSE(point->confirmed);
  EXPECT_NEAR(k.bounds({w}).allowed.u_max, 0.4, 1e-9);
}

TEST(PanelExtent, WeakReflectionsSayNothingAndTheSupportOverrulesADenialInsideIt) {
  const PlaneCase k;
  PanelWitness far;  // 5 m of extra path: 20 dB down
  far.pair.source_m = {0.5, 1.2, 1.5};
  far.pair.receiver_m = {0.5, 2.2, 1.5};
  EXPECT_FALSE(witnessPoint(k.plane, far, kC).has_value());
  PanelWitness near;  // its point u = 0.1, inside the 0.25 m round the supporting point
  near.pair.source_m = {3.7, 2.2, 1.5};
  near.pair.receiver_m = {3.7, 2.6, 1.5};
  const auto point = witnessPoint(k.plane, near, kC);
  ASSERT_TRUE(point.has_value());
  EXPECT_NEAR(point->at.x(), 0.1, 1e-9);
  const PanelBounds b = k.bounds({near});
  EXPECT_NEAR(b.allowed.width(), 2.0 * kMaxPanelHalfM, 1e-9);
  EXPECT_NEAR(b.allowed.height(), 2.0 * kMaxPanelHalfM, 1e-9);
}

}  // namespace
}  // namespace room_reverb::test
