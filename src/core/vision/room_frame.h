#pragma once
// The fitted room box as the later steps need it: the rig-to-room transform and, for a
// point in the room frame, how far it is from each face and whether it lies on one.
#include <Eigen/Core>
#include <array>
#include <cmath>

namespace room_reverb::core::layout {

struct RoomFrame {
  RoomFrame(double rig_yaw_rad, const Eigen::Vector3d& rig_position, const Eigen::Vector3d& size, bool has_ceiling,
            const std::array<double, 6>& margin)
      : rig_yaw_rad(rig_yaw_rad), rig_position(rig_position), size(size), has_ceiling(has_ceiling), margin(margin),
        cos_(std::cos(rig_yaw_rad)), sin_(std::sin(rig_yaw_rad)) {}

  double rig_yaw_rad;            // rotation rig -> room about z
  Eigen::Vector3d rig_position;  // the rig in the room frame
  Eigen::Vector3d size;
  bool has_ceiling;
  // Each face's half thickness (kRoomSurfaceNames order): points this close lie on it.
  std::array<double, 6> margin;

  Eigen::Vector3d toRoom(const Eigen::Vector3d& rig_point) const {
    return Eigen::Vector3d(cos_ * rig_point.x() - sin_ * rig_point.y(), sin_ * rig_point.x() + cos_ * rig_point.y(),
                           rig_point.z()) +
           rig_position;
  }

  // Signed distance into the room from each face (kRoomSurfaceNames order).
  std::array<double, 6> faceDistances(const Eigen::Vector3d& p) const {
    return {p.z(), size.z() - p.z(), p.x(), size.x() - p.x(), p.y(), size.y() - p.y()};
  }

  bool usesFace(int face) const { return face != 1 || has_ceiling; }

  // Inside the box and clear of every face by its margin: where furniture can be.
  bool clearOfFaces(const Eigen::Vector3d& p) const {
    const auto d = faceDistances(p);
    for (int f = 0; f < 6; ++f) {
      if (usesFace(f) && d[f] <= margin[f]) return false;
    }
    return true;
  }

  // Inside the box grown by the margins (not a stray beyond the walls).
  bool inside(const Eigen::Vector3d& p) const {
    const auto d = faceDistances(p);
    for (int f = 0; f < 6; ++f) {
      if (usesFace(f) && d[f] < -margin[f]) return false;
    }
    return true;
  }

  // The face a point lies on: the nearest in units of its margin, within its margin; -1
  // if none (inside the room away from the faces, or beyond them).
  int faceOf(const Eigen::Vector3d& p) const {
    if (!inside(p)) return -1;
    const auto d = faceDistances(p);
    int face = -1;
    double best = 1.0;
    for (int f = 0; f < 6; ++f) {
      if (!usesFace(f)) continue;
      const double r = std::abs(d[f]) / margin[f];
      if (r <= best) best = r, face = f;
    }
    return face;
  }

 private:
  double cos_, sin_;
};

}  // namespace room_reverb::core::layout
