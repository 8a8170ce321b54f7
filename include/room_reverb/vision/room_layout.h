#pragma once
// The room's geometry from a point cloud of the visual route: where the walls, floor and
// ceiling are relative to the rig, and the furniture as labelled upright cuboids.
//
// Input: a cloud in the `rig` frame (origin at the camera pair's centre), levelled (z up,
// from the capture's gravity alignment) but with the rig's yaw relative to the walls
// unknown. The room is taken to be a box (a Manhattan world: four walls at right angles,
// a horizontal floor, a horizontal ceiling or none).
//
// Steps (each in its own file under src/core/vision/):
//  1. Voxel grid (voxel_grid.h): one centroid per occupied voxel, so plane support is
//     area, not the range-dependent point density of stereo.
//  2. Floor and ceiling (room_box_fit.h): peaks of the histogram of heights; the floor is
//     the lowest dense plane below the rig, the ceiling the highest above it, if there is
//     one strong enough (else has_ceiling = false).
//  3. Yaw (manhattan_frame.h): the rotation that makes the plan view sharpest (points
//     between floor and ceiling), refined by line fits to the walls' points. Target: well
//     under 1 degree.
//  4. Walls (room_box_fit.h): on each side of the rig along each wall direction, the
//     vertical plane where the ceiling (or floor) ends (surface_edge.h), chosen among the
//     wall's layers (a recessed door, a radiator, a kitchen run) as the one with the most
//     area; the edge itself where furniture or clutter hides the wall; an open side where
//     the ground runs on with nothing standing at its end. Without such an edge, the
//     innermost dense plane that stops more of the rig's rays than get past it (not the
//     extreme point: stereo strays and facades seen through windows lie beyond the walls;
//     not a sideboard's front: the wall behind it stops more rays). Positions are
//     weighted medians in windows that grow with the wall's distance (depth noise grows
//     with range). Given the top image (LayoutImage), a wall placed without a plane at
//     the ceiling's edge moves to where the image shows the ceiling meeting it, if it
//     shows that clearly (wall_junctions.h).
//  5. Room frame: see RoomLayout::room_from_rig.
//  6. Objects (furniture_fit.h: object_clusters.h, cluster_split.h, cuboid_fit.h,
//     hidden_sides.h, furniture_labels.h): voxels inside the box and clear of its faces by
//     each face's noise margin (the calibrated noise, or the spread the face's own points
//     show where that is more: face_spread.h), grouped into connected clusters; a cluster
//     is split where only thin bridges of smeared or stray stereo points join its pieces,
//     and clusters are joined where they are one piece seen in parts (their cuboids
//     overlap, or hardly a ray passes through the cuboid of both); each large enough
//     cluster becomes an upright cuboid (yaw from the closeness of its points to a
//     rectangle's sides, or the walls'), its hidden sides carved out against the rays that
//     passed behind them (on the floor, against a wall when nothing shows they are not),
//     and named by its size.
//
// Cost: linear in the points; about 0.4 s for a million points on one core.
//
// Materials are not chosen here: every surface and object gets an empty material name
// with confidence 0 (a placeholder the material step fills, using point_surface and
// point_object to find each face's and object's points and colours). Until then the model
// is not a valid room.yaml (saveRoomModel rejects empty materials).
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <opencv2/core.hpp>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/vision/oriented_box_iou.h"
#include "room_reverb/vision/point_cloud.h"

namespace room_reverb::core {

struct RoomLayoutOptions {
  // Voxel edge [m]: the resolution of everything; smaller is slower and needs a denser
  // cloud.
  double voxel_size_m = 0.05;
  // Points farther from the rig are ignored [m] (stereo reports sky and glass at huge depths).
  double max_range_m = 40.0;
  // Fewer points than this is an error: a room's planes cannot be told from noise.
  std::size_t min_points = 2000;
  // 1-sigma depth noise of the cloud as a fraction of the range (stereo calibration).
  // Sets how thick a plane looks: a face at distance d is taken to be +-noise_sigmas *
  // range_noise_fraction * d thick (but at least min_face_margin_m), both when fitting it
  // and when cutting it away from the furniture (there thicker if the face's points
  // spread more).
  double range_noise_fraction = 0.01;
  // Depth noisier than that (compressed images, a poorer camera or matcher) spreads the
  // floor into a layer no window of that width holds. With no floor found, the floor and
  // ceiling are searched again with the fraction multiplied by each of these in turn (the
  // first that finds one serves, with a warning naming it; the walls keep the calibrated
  // fraction). Empty: no retry.
  std::vector<double> noise_fraction_retries = {1.5, 2.0, 3.0};
  double noise_sigmas = 3.0;
  double min_face_margin_m = 0.06;
  // A plane needs this much area [m^2] (counted in voxels) and this density contrast to its
  // surroundings (see PlaneHistogram::peaks in src/core/vision/plane_histogram.h).
  double min_plane_area_m2 = 0.5;
  double min_plane_contrast = 3.0;
  // Wall layers (see src/core/vision/room_box_fit.h): the contrast a layer needs where
  // the ceiling's or floor's edge confirms it, how far apart the layers of one wall lie
  // [m], how far beyond that edge a layer may be [m], and how far beyond it (a dense
  // plane) or inside it (the outermost plane) a wall may lie where furniture ends the
  // ceiling or hides the wall [m].
  double min_layer_contrast = 1.4;
  double wall_layer_gap_m = 0.25;
  double wall_edge_tolerance_m = 0.2;
  double hidden_wall_m = 0.5;
  // A wall the depth places without a plane where the ceiling ends (a far wall of a few
  // pixels of disparity, a ceiling ranged short of its wall) is placed where the top image
  // shows the ceiling meeting it, if it shows that clearly (needs the image:
  // fitRoomLayout's `image`; src/core/vision/wall_junctions.h).
  bool wall_ceiling_junctions = true;
  // A plane is a candidate for a wall or the floor if it has at least this fraction of the
  // strongest plane's support on its side of the rig (a wall partly hidden by a wardrobe
  // is still the wall).
  double outer_plane_fraction = 0.3;
  // The room has a ceiling if the strongest plane above the rig has at least this fraction
  // of the floor's support.
  double ceiling_min_support_fraction = 0.15;
  // Objects: occupied voxels closer than object_gap_m [m] (rounded to whole voxels, at
  // least one) belong to the same cluster; clusters of fewer voxels than
  // min_object_voxels, or whose largest side is shorter than min_object_extent_m [m], are
  // dropped.
  double object_gap_m = 0.1;
  std::size_t min_object_voxels = 30;
  double min_object_extent_m = 0.15;
  // An object's face this close [m] beyond the cut of a room face is moved onto it (the
  // bottom onto the floor; a side onto the wall it stands against).
  double object_contact_m = 0.1;
  // An object's yaw (the one at which its points lie closest to the sides of their
  // rectangle) is snapped to the walls' directions if within object_manhattan_snap_rad
  // [rad] of them, or if the fit square to the walls scores within
  // object_manhattan_tolerance (a fraction) of the best: most furniture stands square to
  // the walls, and a poorly seen object decides nothing.
  double object_manhattan_snap_rad = 0.0873;  // 5 degrees
  double object_manhattan_tolerance = 0.05;
  // Two clusters whose cuboids share this fraction of the smaller one's volume are merged
  // into one object (an object seen in parts).
  double object_merge_overlap = 0.25;
  // A cluster is cut into side-by-side pieces where the height of its top steps by at
  // least object_step_m [m] along its length (a base run and the fridge at its end), and
  // into stacked pieces at an empty horizontal band at least object_stack_gap_m [m] high
  // across it (wall units above a worktop); see src/core/vision/cluster_profile_split.h.
  // 0 turns a cut off.
  double object_step_m = 0.3;
  double object_stack_gap_m = 0.4;
  // Object extents are taken between these quantiles of its points (and 1 - it).
  double object_extent_quantile = 0.01;
  // Sides of an object the rig cannot see (see src/core/vision/hidden_sides.h): moved onto
  // a wall up to this far [m] behind them if no ray was seen between; an object thinner
  // than object_min_depth_m towards a hidden side is deepened to it as far as the rays
  // allow; object_free_rays rays through a region prove it empty.
  double object_max_gap_to_wall_m = 1.0;
  double object_min_depth_m = 0.4;
  std::size_t object_free_rays = 5;
  // Fill RoomLayout::point_surface and point_object (one int per input point each).
  bool assign_points = true;
};

// The material of an open side (the library's opening: absorbs every band).
inline constexpr const char* kOpenSideMaterial = "open_window";

// What a face of the fitted box rests on, and how sure the fit is of it.
struct FaceEvidence {
  // "plane at the ceiling's or floor's edge", "plane", "ceiling or floor edge (wall
  // hidden)" or
  // "open side" (walls); "plane" for the floor and ceiling.
  std::string basis;
  double confidence = 0.0;  // 0..1
  bool open = false;        // an open side: its material is the library's open_window
};

// The relief of a face or an object (vision/surface_relief.h): how much of it the cloud
// shows, how much of that stands off its plane(s), and the scattering that gives.
struct ReliefEstimate {
  bool estimated = false;     // false: not seen enough, an open side, or absent
  double seen_m2 = 0.0;       // area of the seen cells
  double relief_share = 0.0;  // of the seen cells, those off the face's plane
  double rms_height_m = 0.0;  // over the seen cells (0 for a plane face)
  OctaveBandValues scattering{};
};

struct RoomLayout {
  // size_m, has_ceiling (size_m.z() is then the walls' top), objects (label, centre, size,
  // yaw, confidence; material empty), the rig pose in the room frame, and all six surfaces
  // (five without a ceiling) with material "" and confidence 0.
  RoomModel model;
  // p_room = room_from_rig * p_rig. The room frame: origin at the floor corner where the
  // walls x_min and y_min meet, x and y along the walls, z up. Of the four wall directions,
  // x is the one closest to the rig's +x, so a rig set up roughly square to the room keeps
  // x as "forward"; the rig's yaw in the room is then in [-45, 45) degrees (at exactly 45
  // degrees either choice is as good).
  Eigen::Isometry3d room_from_rig = Eigen::Isometry3d::Identity();
  // The rig's yaw in the room frame [rad], in [-pi/4, pi/4).
  double rig_yaw_rad = 0.0;
  // How much of each face was seen (kRoomSurfaceNames order), in voxels (area / voxel^2).
  std::array<double, 6> surface_support{};
  // Per face (kRoomSurfaceNames order): what its position rests on.
  std::array<FaceEvidence, 6> face_evidence{};
  // Per face (kRoomSurfaceNames order) and per object: its relief, where the visual route
  // estimated it (fitRoomLayout leaves them empty).
  std::array<ReliefEstimate, 6> face_relief{};
  std::vector<ReliefEstimate> object_relief;
  // One line per thing a user should check: a wall placed without a plane of its own, an
  // open side, an object changed to keep the model simulable.
  std::vector<std::string> warnings;
  // Per input point: the face it lies on (index into kRoomSurfaceNames) or -1; the object
  // it belongs to (index into model.objects) or -1. Empty unless options.assign_points.
  std::vector<std::int32_t> point_surface;
  std::vector<std::int32_t> point_object;
};

// Throws InputError for an empty cloud, fewer than options.min_points points, a
// non-finite point, non-positive or non-finite options, and a cloud that shows no room:
// no floor plane below the rig, or a side without a wall (a random blob of points, a
// single plane).
// The top camera's image, for what the cloud does not hold: where a wall meets the floor
// and the ceiling (src/core/vision/wall_junctions.h).
struct LayoutImage {
  cv::Mat color;                                                  // the top camera's equirect, 8-bit BGR
  Eigen::Isometry3d camera_from_rig = Eigen::Isometry3d::Identity();  // the cloud's frame -> the top camera's
};
RoomLayout fitRoomLayout(const PointCloud& cloud, const RoomLayoutOptions& options = {},
                         const LayoutImage* image = nullptr);

}  // namespace room_reverb::core
