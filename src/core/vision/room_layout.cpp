#include "room_reverb/vision/room_layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

#include "face_spread.h"
#include "furniture_fit.h"
#include "manhattan_frame.h"
#include "room_box_fit.h"
#include "room_reverb/acoustics/cuboid.h"
#include "room_reverb/common/error.h"
#include "room_reverb/vision/room_model_cleanup.h"
#include "voxel_grid.h"
#include "wall_junctions.h"

namespace room_reverb::core {

namespace {

using layout::AlignedBox;

void checkOptions(const RoomLayoutOptions& o) {
  const auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw InputError(std::string("room layout options: ") + name + " must be positive and finite");
    }
  };
  const auto non_negative = [](double v, const char* name) {
    if (!(v >= 0.0) || !std::isfinite(v)) {
      throw InputError(std::string("room layout options: ") + name + " must be non-negative and finite");
    }
  };
  positive(o.voxel_size_m, "voxel_size_m");
  positive(o.max_range_m, "max_range_m");
  non_negative(o.range_noise_fraction, "range_noise_fraction");
  positive(o.noise_sigmas, "noise_sigmas");
  for (const double factor : o.noise_fraction_retries) {
    if (!(factor > 1.0) || !std::isfinite(factor)) {
      throw InputError("room layout options: each of noise_fraction_retries must be a finite factor above 1");
    }
  }
  positive(o.min_face_margin_m, "min_face_margin_m");
  positive(o.min_plane_area_m2, "min_plane_area_m2");
  positive(o.min_plane_contrast, "min_plane_contrast");
  positive(o.outer_plane_fraction, "outer_plane_fraction");
  positive(o.min_layer_contrast, "min_layer_contrast");
  non_negative(o.wall_layer_gap_m, "wall_layer_gap_m");
  non_negative(o.wall_edge_tolerance_m, "wall_edge_tolerance_m");
  non_negative(o.hidden_wall_m, "hidden_wall_m");
  non_negative(o.ceiling_min_support_fraction, "ceiling_min_support_fraction");
  non_negative(o.min_object_extent_m, "min_object_extent_m");
  non_negative(o.object_gap_m, "object_gap_m");
  non_negative(o.object_contact_m, "object_contact_m");
  non_negative(o.object_manhattan_snap_rad, "object_manhattan_snap_rad");
  non_negative(o.object_manhattan_tolerance, "object_manhattan_tolerance");
  non_negative(o.object_merge_overlap, "object_merge_overlap");
  non_negative(o.object_step_m, "object_step_m");
  non_negative(o.object_stack_gap_m, "object_stack_gap_m");
  non_negative(o.object_max_gap_to_wall_m, "object_max_gap_to_wall_m");
  non_negative(o.object_min_depth_m, "object_min_depth_m");
  if (o.object_free_rays < 1) throw InputError("room layout options: object_free_rays must be at least 1");
  if (!(o.object_extent_quantile >= 0.0 && o.object_extent_quantile < 0.5)) {
    throw InputError("room layout options: object_extent_quantile must be in [0, 0.5)");
  }
  if (o.voxel_size_m * (1 << 20) < o.max_range_m) {
    throw InputError("room layout options: voxel_size_m too small for max_range_m (over 2^20 voxels across)");
  }
}

layout::BoxFitParams boxFitParams(const RoomLayoutOptions& o) {
  layout::BoxFitParams p;
  p.spread = {o.min_face_margin_m, o.range_noise_fraction, o.noise_sigmas};
  p.min_plane_support = o.min_plane_area_m2 / (o.voxel_size_m * o.voxel_size_m);
  p.min_plane_contrast = o.min_plane_contrast;
  p.outer_plane_fraction = o.outer_plane_fraction;
  p.ceiling_min_support_fraction = o.ceiling_min_support_fraction;
  p.min_layer_contrast = o.min_layer_contrast;
  p.layer_gap_m = o.wall_layer_gap_m;
  p.edge_tolerance_m = o.wall_edge_tolerance_m;
  p.hidden_wall_m = o.hidden_wall_m;
  return p;
}

Eigen::Vector3d rotateZ(const Eigen::Vector3d& p, double c, double s) {
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z()};
}

std::vector<Eigen::Vector3d> rotatedByMinus(const std::vector<Eigen::Vector3d>& points, double yaw) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(points.size());
  const double c = std::cos(yaw), s = -std::sin(yaw);
  for (const auto& p : points) out.push_back(rotateZ(p, c, s));
  return out;
}

// Each wall's points (plan, rig frame) for the yaw refinement: structure voxels between
// floor and ceiling within the wall's window and between the walls across it.
std::vector<layout::WallPoints> wallPoints(const std::vector<Eigen::Vector3d>& rig_points,
                                           const std::vector<Eigen::Vector3d>& aligned, const AlignedBox& box,
                                           const layout::PlaneSpread& spread) {
  std::vector<layout::WallPoints> walls(4);
  const double z_lo = box.floor_z + box.margin(0, spread);
  const double z_hi = box.has_ceiling ? box.top_z - box.margin(1, spread) : std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    const Eigen::Vector3d& a = aligned[i];
    if (a.z() <= z_lo || a.z() >= z_hi) continue;
    for (int face = 2; face < 6; ++face) {
      const int axis = (face - 2) / 2, other = 1 - axis;
      const double lo = box.facePosition(2 + 2 * other) + box.margin(2 + 2 * other, spread);
      const double hi = box.facePosition(3 + 2 * other) - box.margin(3 + 2 * other, spread);
      if (std::abs(a[axis] - box.facePosition(face)) <= box.margin(face, spread) && a[other] > lo && a[other] < hi) {
        walls[face - 2].plan.push_back(rig_points[i].head<2>());
      }
    }
  }
  return walls;
}

// The raw points not hinted to be furniture in the aligned frame (rotated by -yaw into
// the walls' axes), each weighted by one over its voxel's count.
std::vector<layout::WeightedPoint> alignedRaw(const PointCloud& cloud, const layout::VoxelGrid& grid, double yaw) {
  const auto& voxels = grid.voxels();
  const float c = static_cast<float>(std::cos(-yaw)), s = static_cast<float>(std::sin(-yaw));
  std::vector<layout::WeightedPoint> raw;
  raw.reserve(cloud.points.size());
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const std::uint32_t v = grid.pointVoxel()[i];
    if (v == layout::VoxelGrid::kNoVoxel || voxels[v].hint == layout::VoxelHint::object) continue;
    const Eigen::Vector3f& p = cloud.points[i].p;
    const Eigen::Vector3f aligned(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z());
    raw.push_back({aligned, 1.0f / static_cast<float>(voxels[v].count)});
  }
  return raw;
}

// Each face's evidence, and a warning for each wall that rests on less than a plane where
// the ceiling or floor ends.
void recordFaceEvidence(const AlignedBox& box, RoomLayout& result) {
  for (int f = 0; f < 6; ++f) {
    const layout::WallChoice& choice = box.choice[static_cast<std::size_t>(f)];
    FaceEvidence& evidence = result.face_evidence[static_cast<std::size_t>(f)];
    evidence.confidence = choice.confidence;
    const std::string name = kRoomSurfaceNames[static_cast<std::size_t>(f)];
    const double distance = std::abs(box.facePosition(f));
    char where[64];
    std::snprintf(where, sizeof where, "%.2f m from the rig", distance);
    switch (choice.basis) {
      case layout::WallBasis::kPlaneAtEdge:
        evidence.basis = "plane at the ceiling's or floor's edge";
        break;
      case layout::WallBasis::kPlane:
        evidence.basis = "plane";
        if (f >= 2) {
          result.warnings.push_back(name + ": a plane " + where +
                                    ", with no ceiling or floor edge to confirm it is the wall");
        }
        break;
      case layout::WallBasis::kEdge:
        evidence.basis = "ceiling or floor edge (wall hidden)";
        result.warnings.push_back(name + ": no wall plane where the ceiling or floor ends; placed at that edge, " +
                                  where + " (furniture or clutter hides the wall)");
        break;
      case layout::WallBasis::kRayStop:
        evidence.basis = "where the rays aimed past the ceiling's ranged edge stop";
        result.warnings.push_back(name + ": no wall plane where the ceiling's range ends; placed where the rays aimed "
                                  "past that edge stop, " + where + " (the ceiling near the wall has no range: a light "
                                  "panel or a plain surface)");
        break;
      case layout::WallBasis::kScatteredPlane:
        evidence.basis = "plane at the floor's edge, its points scattered";
        result.warnings.push_back(name + ": its points scatter far beyond the stereo's usual noise (a plain or far "
                                  "wall); placed at their plane where the floor ends, " + where);
        break;
      case layout::WallBasis::kCeilingJunction:
        evidence.basis = "where the image shows the ceiling meeting it";  // warned where it is placed
        break;
      case layout::WallBasis::kOpen:
        evidence.basis = "open side";
        evidence.open = true;
        result.warnings.push_back(name + ": nothing stands where the floor ends, " + where +
                                  "; an open side (material " + kOpenSideMaterial + ")");
        break;
    }
  }
}

// The object a point of a furniture cluster lies on after the clean-up cut, split or
// dropped its cuboid: the nearest within `reach_m`, or -1.
std::int32_t nearestObject(const std::vector<CuboidObject>& objects, const Eigen::Vector3d& p, double reach_m) {
  std::int32_t best = -1;
  double nearest = reach_m;
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const double d = distanceToCuboid(objects[k], p);
    if (d <= nearest) nearest = d, best = static_cast<std::int32_t>(k);
  }
  return best;
}

// Walls the depth places without a plane at the ceiling's edge (kEdge, kRayStop, kPlane:
// a far wall of few pixels of disparity, a wall the ceiling's range stops short of) are
// placed where the image shows the ceiling meeting them, when it shows that clearly
// (wall_junctions.h) and that lies more than one of its pixels from the depth's position.
// Walls resting on a plane at the ceiling's edge keep it: the depth there is the better
// measure (a pixel of a junction 7 m away at 1024 px is 0.22 m). Returns a warning per
// wall moved.
std::vector<std::string> placeWallsAtCeilingJunctions(AlignedBox& box, const std::vector<layout::WeightedPoint>& raw,
                                                      const cv::Mat& color, const Eigen::Isometry3d& camera_from_aligned) {
  std::vector<std::string> notes;
  if (!box.has_ceiling) return notes;
  cv::Mat image;  // prepared when a wall first needs it
  for (int face = 2; face < 6; ++face) {
    layout::WallChoice& choice = box.choice[static_cast<std::size_t>(face)];
    if (choice.basis != layout::WallBasis::kEdge && choice.basis != layout::WallBasis::kRayStop &&
        choice.basis != layout::WallBasis::kPlane) {
      continue;
    }
    if (image.empty()) image = layout::junctionImage(color);
    const layout::JunctionFit junction = layout::ceilingJunction(image, camera_from_aligned, box, face, {});
    const double depth_position = box.facePosition(face);
    // Within a pixel of the depth's position the junction adds nothing the depth does not
    // measure more finely.
    if (!junction.found || std::abs(junction.position_m - depth_position) <= junction.pixel_m) continue;
    // Further out than the depth's wall, the line must be in the rig's sight: the rays to
    // the wall just under it (three pixels) may not stop a tenth of the way short of it.
    // Nearer, the rays to the top of the wall under it (the upper 30 % of the wall above
    // the camera, where furniture seldom stands) may not go on a tenth of the way beyond
    // it: just under the line itself they would meet the ceiling beyond it, as near as
    // the wall would be.
    const bool outwards = std::abs(junction.position_m) > std::abs(depth_position);
    const double camera_z = camera_from_aligned.inverse().translation().z();
    const double band_m = outwards ? 3.0 * junction.pixel_m * (box.top_z - camera_z) / std::abs(junction.position_m)
                                   : 0.3 * (box.top_z - camera_z);
    if (!layout::raysMeetJunction(raw, box, face, junction.position_m, outwards, camera_z, band_m,
                                  0.1 * std::abs(junction.position_m), {})) {
      continue;
    }
    switch (face) {
      case 2: box.x_lo = junction.position_m; break;
      case 3: box.x_hi = junction.position_m; break;
      case 4: box.y_lo = junction.position_m; break;
      default: box.y_hi = junction.position_m; break;
    }
    const char* depth_basis = choice.basis == layout::WallBasis::kPlane      ? "on a plane no ceiling edge confirms"
                              : choice.basis == layout::WallBasis::kRayStop ? "where the rays past the ceiling's edge stop"
                                                                            : "at the ceiling's ranged edge";
    choice = {junction.position_m, layout::WallBasis::kCeilingJunction, 0.5, 0.0};
    char line[320];
    std::snprintf(line, sizeof line,
                  "%s: placed where the image shows the ceiling meeting it, %.2f m from the rig (+-%.2f m a pixel); "
                  "the depth alone placed it %s, %.2f m away",
                  kRoomSurfaceNames[static_cast<std::size_t>(face)], std::abs(junction.position_m), junction.pixel_m,
                  depth_basis, std::abs(depth_position));
    notes.emplace_back(line);
  }
  return notes;
}

layout::FurnitureParams furnitureParams(const RoomLayoutOptions& o, const layout::RoomFrame& frame) {
  layout::FurnitureParams p;
  p.cuboid.room_size = frame.size;
  p.cuboid.face_margin = frame.margin;
  p.cuboid.extent_quantile = o.object_extent_quantile;
  p.cuboid.manhattan_snap_rad = o.object_manhattan_snap_rad;
  p.cuboid.manhattan_tolerance = o.object_manhattan_tolerance;
  p.cuboid.contact_m = o.object_contact_m;
  p.cuboid.rig_position = frame.rig_position;
  p.cuboid.noise_fraction = o.range_noise_fraction;
  p.hidden.rig_position = frame.rig_position;
  p.hidden.room_size = frame.size;
  p.hidden.noise_fraction = o.range_noise_fraction;
  p.hidden.noise_sigmas = o.noise_sigmas;
  p.hidden.inset_m = 0.5 * o.voxel_size_m;
  p.hidden.max_to_wall_m = o.object_max_gap_to_wall_m;
  p.hidden.min_depth_m = o.object_min_depth_m;
  p.hidden.free_rays = o.object_free_rays;
  p.min_voxels = o.min_object_voxels;
  p.link_voxels = std::max(1, static_cast<int>(std::lround(o.object_gap_m / o.voxel_size_m)));
  p.min_extent_m = o.min_object_extent_m;
  p.merge_overlap = o.object_merge_overlap;
  p.profile.step_m = o.object_step_m;
  p.profile.stack_gap_m = o.object_stack_gap_m;
  return p;
}

// The floor and ceiling at the calibrated depth noise, or else each at the first of the
// noisier retries that finds it. Only the search for them is widened: the noise is the
// floor's and ceiling's (low texture seen at a grazing angle loses most to compression; a
// plain ceiling under sensor noise keeps few ranges, and those noisy), and walls fitted
// with windows that wide take inner layers for the wall (measured on rendered rooms: 6-9 %
// short across one axis). A ceiling is looked for more widely only where the calibrated
// search found a floor but none above: a layer above the rig as dense as the ceiling rule
// asks (a share of the floor's support) is a ceiling ranged poorly, not sky.
layout::HorizontalPlanes floorAndCeiling(const std::vector<double>& heights, const RoomLayoutOptions& options,
                                         std::vector<std::string>& warnings) {
  const auto note = [&](const char* surface, double fraction) {
    std::ostringstream line;
    line << "depth noise: no " << surface << " at " << 100.0 * options.range_noise_fraction
         << " % of the range; found as a layer " << 100.0 * fraction << " % thick (compressed or noisy images?)";
    warnings.push_back(line.str());
  };
  RoomLayoutOptions noisier = options;
  try {
    layout::HorizontalPlanes planes = layout::findHorizontalPlanes(heights, boxFitParams(options));
    for (std::size_t k = 0; k < options.noise_fraction_retries.size() && !planes.has_ceiling; ++k) {
      noisier.range_noise_fraction = options.range_noise_fraction * options.noise_fraction_retries[k];
      layout::HorizontalPlanes wider;
      try {
        wider = layout::findHorizontalPlanes(heights, boxFitParams(noisier));
      } catch (const InputError&) {
        continue;  // no floor in windows this wide: the calibrated floor stands, without a ceiling from them
      }
      if (!wider.has_ceiling) continue;
      planes.has_ceiling = true;
      planes.ceiling_z = wider.ceiling_z;
      planes.ceiling_support = wider.ceiling_support;
      note("ceiling", noisier.range_noise_fraction);
    }
    return planes;
  } catch (const InputError&) {
    for (const double factor : options.noise_fraction_retries) {
      noisier.range_noise_fraction = options.range_noise_fraction * factor;
      try {
        layout::HorizontalPlanes planes = layout::findHorizontalPlanes(heights, boxFitParams(noisier));
        note("floor", noisier.range_noise_fraction);
        return planes;
      } catch (const InputError&) {
      }
    }
    throw;
  }
}

}  // namespace

RoomLayout fitRoomLayout(const PointCloud& cloud, const RoomLayoutOptions& options, const LayoutImage* image) {
  checkOptions(options);
  checkPointCloud(cloud, options.min_points);
  const layout::VoxelGrid grid(cloud, options.voxel_size_m, options.max_range_m);
  const auto& voxels = grid.voxels();

  // Planes are fitted to every voxel not hinted to be furniture.
  std::vector<Eigen::Vector3d> structure;
  structure.reserve(voxels.size());
  for (const auto& v : voxels) {
    if (v.hint != layout::VoxelHint::object) structure.push_back(v.centroid);
  }
  if (structure.size() < 100) {
    throw InputError("room layout: only " + std::to_string(structure.size()) +
                     " occupied voxels within max_range_m; the cloud is too sparse or too small to hold a room");
  }
  std::vector<double> heights;
  heights.reserve(structure.size());
  for (const auto& p : structure) heights.push_back(p.z());
  std::vector<std::string> noise_warnings;
  const layout::HorizontalPlanes planes = floorAndCeiling(heights, options, noise_warnings);
  const layout::BoxFitParams params = boxFitParams(options);
  const layout::PlaneSpread& spread = params.spread;

  // Yaw from the points between floor and ceiling (the floor's and ceiling's outlines are
  // sharp too, but the walls are what the room frame is aligned to).
  std::vector<Eigen::Vector2d> plan;
  const double band_lo = planes.floor_z + params.band_margin_m;
  const double band_hi =
      planes.has_ceiling ? planes.ceiling_z - params.band_margin_m : std::numeric_limits<double>::infinity();
  for (const auto& p : structure) {
    if (p.z() > band_lo && p.z() < band_hi) plan.push_back(p.head<2>());
  }
  if (plan.size() < 100) {
    throw InputError(
        "room layout: (almost) no points between floor and ceiling, so no walls; the cloud must show the walls");
  }
  double yaw = layout::sharpestPlanYaw(plan, 0.5 * options.voxel_size_m);
  AlignedBox box =
      layout::fitAlignedBox(rotatedByMinus(structure, yaw), alignedRaw(cloud, grid, yaw), planes, params);
  yaw = layout::refineYawFromWalls(yaw, wallPoints(structure, rotatedByMinus(structure, yaw), box, spread));
  // The room's x: the wall direction nearest the rig's +x, i.e. the rig's yaw in the room
  // in [-pi/4, pi/4).
  const double rig_yaw = layout::wrapQuarterTurn(-yaw);
  yaw = -rig_yaw;
  const auto raw = alignedRaw(cloud, grid, yaw);
  box = layout::fitAlignedBox(rotatedByMinus(structure, yaw), raw, planes, params);

  if (!box.has_ceiling) box.top_z = layout::wallTopEdge(raw, box, spread);
  std::vector<std::string> junction_notes;
  if (image != nullptr && options.wall_ceiling_junctions) {
    const Eigen::Isometry3d camera_from_aligned =
        image->camera_from_rig * Eigen::Isometry3d(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    junction_notes = placeWallsAtCeilingJunctions(box, raw, image->color, camera_from_aligned);
  }

  // Furniture is cut away from each face by the face's thickness: the calibrated noise,
  // or more where the face's own points show more (a plain wall, a smaller image).
  const std::array<double, 6> measured = layout::measuredFaceSpreads(raw, box, spread);
  std::array<double, 6> margin{};
  for (int f = 0; f < 6; ++f) margin[f] = std::max(box.margin(f, spread), spread.sigmas * measured[f]);
  const layout::RoomFrame frame(rig_yaw, -Eigen::Vector3d(box.x_lo, box.y_lo, box.floor_z),
                                Eigen::Vector3d(box.x_hi - box.x_lo, box.y_hi - box.y_lo, box.top_z - box.floor_z),
                                box.has_ceiling, margin);

  RoomLayout result;
  result.warnings = noise_warnings;
  RoomModel& model = result.model;
  model.frame = "room";
  model.size_m = frame.size;
  model.has_ceiling = box.has_ceiling;
  for (const char* name : kRoomSurfaceNames) {
    if (std::string(name) == "ceiling" && !box.has_ceiling) continue;
    model.surfaces[name] = SurfaceAssignment{"", 0.0};  // placeholder: the material step names it
  }
  model.rig_position_m = frame.rig_position;
  model.rig_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(rig_yaw, Eigen::Vector3d::UnitZ()));
  result.rig_yaw_rad = rig_yaw;
  result.room_from_rig =
      Eigen::Translation3d(frame.rig_position) * Eigen::AngleAxisd(rig_yaw, Eigen::Vector3d::UnitZ());
  result.surface_support = box.support;
  recordFaceEvidence(box, result);
  result.warnings.insert(result.warnings.end(), junction_notes.begin(), junction_notes.end());
  for (int f = 2; f < 6; ++f) {
    if (result.face_evidence[static_cast<std::size_t>(f)].open) {
      model.surfaces[kRoomSurfaceNames[static_cast<std::size_t>(f)]] = SurfaceAssignment{kOpenSideMaterial, 0.3};
    }
  }

  const layout::Furniture furniture = layout::fitFurniture(cloud, grid, frame, furnitureParams(options, frame));
  model.objects = furniture.objects;
  // Objects cut back to the box, hidden ones dropped, free air around the rig: a model the
  // simulator takes as it is (room_model_cleanup.h).
  const std::vector<std::string> cleanup_notes = cleanUpRoomModel(model);
  for (const std::string& note : cleanup_notes) result.warnings.push_back("objects: " + note);
  const bool objects_changed = !cleanup_notes.empty();

  if (options.assign_points) {
    const double max_range2 = options.max_range_m * options.max_range_m;
    result.point_surface.assign(cloud.points.size(), -1);
    result.point_object.assign(cloud.points.size(), -1);
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
      const Eigen::Vector3d rig_point = cloud.points[i].p.cast<double>();
      if (rig_point.squaredNorm() > max_range2) continue;
      const Eigen::Vector3d p = frame.toRoom(rig_point);
      const std::uint32_t v = grid.pointVoxel()[i];
      std::int32_t object = v == layout::VoxelGrid::kNoVoxel ? -1 : furniture.voxel_object[v];
      if (object >= 0 && objects_changed) object = nearestObject(model.objects, p, options.voxel_size_m);
      if (object >= 0 && frame.clearOfFaces(p)) {
        result.point_object[i] = object;
      } else {
        result.point_surface[i] = frame.faceOf(p);
      }
    }
  }
  return result;
}

}  // namespace room_reverb::core
