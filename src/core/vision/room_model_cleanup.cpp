#include "room_reverb/vision/room_model_cleanup.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

// Rounding of a fit flush with a wall is not a crossing.
constexpr double kCrossingToleranceM = 1e-9;

const char* const kAxisNames[] = {"x", "y", "z"};

// The part of the model's list an object came from, for the notes.
struct Piece {
  CuboidObject object;
  std::size_t original = 0;
};

// An object's extent in its own frame (origin at its centre, axes along its sides).
struct Bounds {
  Eigen::Vector3d lo, hi;
  double volume() const { return (hi - lo).cwiseMax(0.0).prod(); }
  double thinnest() const { return (hi - lo).minCoeff(); }  // <= 0: empty
};

Bounds boundsOf(const CuboidObject& object) { return {-0.5 * object.size_m, 0.5 * object.size_m}; }

CuboidObject withBounds(CuboidObject object, const Bounds& bounds) {
  object.center_m = fromCuboidFrame(object, 0.5 * (bounds.lo + bounds.hi));
  object.size_m = bounds.hi - bounds.lo;
  return object;
}

std::string objectName(const Piece& piece) {
  return "object " + std::to_string(piece.original) + " (" + piece.object.label + ")";
}

std::string number(double value) {
  std::ostringstream os;
  os.precision(3);
  os << value;
  return os.str();
}

std::string metres(double value) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(2);
  os << value << " m";
  return os.str();
}

std::string pointText(const Eigen::Vector3d& p) {
  return "(" + number(p.x()) + ", " + number(p.y()) + ", " + number(p.z()) + ") m";
}

void checkInput(const RoomModel& model, const RoomModelCleanup& o) {
  const auto fail = [](const std::string& message) { throw InputError("room model cleanup: " + message); };
  if (!(o.rig_clearance_m >= 0.0) || !std::isfinite(o.rig_clearance_m)) fail("rig_clearance_m must be non-negative and finite");
  if (!(o.min_object_size_m >= 0.0) || !std::isfinite(o.min_object_size_m)) fail("min_object_size_m must be non-negative and finite");
  if (!(o.hidden_fraction > 0.0 && o.hidden_fraction <= 1.0)) fail("hidden_fraction must be in (0, 1]");
  if (!model.size_m.allFinite() || (model.size_m.array() <= 0.0).any()) fail("room_box.size_m must be three positive lengths");
  if (!model.rig_position_m.allFinite()) fail("rig_in_room.position_m must be finite");
  for (std::size_t i = 0; i < model.objects.size(); ++i) {
    const CuboidObject& object = model.objects[i];
    if (!object.center_m.allFinite() || !object.size_m.allFinite() || !std::isfinite(object.yaw_rad) ||
        (object.size_m.array() <= 0.0).any()) {
      fail("objects[" + std::to_string(i) + "] needs a finite centre and yaw and three positive sizes");
    }
  }
}

// Cuts the object back into the box [0, size] (no top without a ceiling); returns how far
// it reached through each face, in kRoomSurfaceNames order, and leaves `bounds` empty
// (lo >= hi somewhere) when nothing of it is inside.
std::array<double, 6> cutToBox(const CuboidObject& object, const RoomModel& model, Bounds& bounds) {
  std::array<double, 6> reach{};
  const Eigen::Vector3d& size = model.size_m;
  const Eigen::Vector3d& center = object.center_m;
  // Height is the same in the object's frame and the room's.
  reach[0] = -(center.z() + bounds.lo.z());
  if (reach[0] > kCrossingToleranceM) bounds.lo.z() = -center.z();
  if (model.has_ceiling) {
    reach[1] = center.z() + bounds.hi.z() - size.z();
    if (reach[1] > kCrossingToleranceM) bounds.hi.z() = size.z() - center.z();
  }
  // Each wall as a half-plane a u + b v + e >= 0 over the object's own (u, v).
  const double c = std::cos(object.yaw_rad), s = std::sin(object.yaw_rad);
  const std::array<std::array<double, 3>, 4> walls = {{
      {c, -s, center.x()},                 // wall_x_min: x >= 0
      {-c, s, size.x() - center.x()},      // wall_x_max: x <= size x
      {s, c, center.y()},                  // wall_y_min: y >= 0
      {-s, -c, size.y() - center.y()},     // wall_y_max: y <= size y
  }};
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const auto [a, b, e] = walls[w];
    // The corner deepest through the wall uses one u bound and one v bound.
    double& u = a >= 0.0 ? bounds.lo.x() : bounds.hi.x();
    double& v = b >= 0.0 ? bounds.lo.y() : bounds.hi.y();
    const double deepest = a * u + b * v + e;
    reach[w + 2] = -deepest;
    if (-deepest <= kCrossingToleranceM) continue;
    // Move the side most nearly facing the wall until that corner is on it.
    if (std::abs(a) >= std::abs(b)) {
      u = -(b * v + e) / a;
    } else {
      v = -(a * u + e) / b;
    }
  }
  return reach;
}

// Step 1: objects cut back to the box, the empty and too thin ones dropped.
std::vector<Piece> cutAllToBox(const RoomModel& model, const RoomModelCleanup& options, std::vector<std::string>& notes) {
  std::vector<Piece> kept;
  for (std::size_t i = 0; i < model.objects.size(); ++i) {
    Piece piece{model.objects[i], i};
    Bounds bounds = boundsOf(piece.object);
    const std::array<double, 6> reach = cutToBox(piece.object, model, bounds);
    std::string crossed;
    for (std::size_t f = 0; f < reach.size(); ++f) {
      if (reach[f] <= kCrossingToleranceM) continue;
      crossed += (crossed.empty() ? "" : ", ") + metres(reach[f]) + " through " + kRoomSurfaceNames[f];
    }
    if (bounds.thinnest() <= 0.0) {
      notes.push_back(objectName(piece) + " dropped: it lies wholly outside the room box");
      continue;
    }
    if (crossed.empty()) {
      kept.push_back(std::move(piece));
      continue;
    }
    // Only what the cut made thin is a sliver; an object fitted thin (a worktop) stays.
    const Eigen::Vector3d cut_size = bounds.hi - bounds.lo;
    const Eigen::Vector3d shortened = piece.object.size_m - cut_size;
    double sliver = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      if (shortened[k] > kCrossingToleranceM) sliver = std::min(sliver, cut_size[k]);
    }
    if (sliver < options.min_object_size_m) {
      notes.push_back(objectName(piece) + " dropped: " + metres(sliver) + " thin once cut back to the room box (it reached " +
                      crossed + "; less than " + metres(options.min_object_size_m) + " is dropped)");
      continue;
    }
    piece.object = withBounds(piece.object, bounds);
    notes.push_back(objectName(piece) + " cut back to the room box: it reached " + crossed);
    kept.push_back(std::move(piece));
  }
  return kept;
}

// Step 2: objects (nearly) inside another dropped, smallest first, each against those at
// least as large.
std::vector<Piece> dropHidden(std::vector<Piece> pieces, const RoomModelCleanup& options, std::vector<std::string>& notes) {
  std::vector<std::size_t> order(pieces.size());
  std::iota(order.begin(), order.end(), 0);
  const auto volume = [&](std::size_t i) { return pieces[i].object.size_m.prod(); };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return volume(a) < volume(b); });
  std::vector<bool> dropped(pieces.size(), false);
  for (std::size_t i : order) {
    for (std::size_t j = 0; j < pieces.size(); ++j) {
      if (j == i || dropped[j]) continue;
      if (volume(j) < volume(i) || (volume(j) == volume(i) && j > i)) continue;
      const double inside = cuboidOverlapM3(pieces[i].object, pieces[j].object) / volume(i);
      if (inside < options.hidden_fraction) continue;
      notes.push_back(objectName(pieces[i]) + " dropped: " + std::to_string(std::lround(100.0 * inside)) +
                      " % of it lies inside " + objectName(pieces[j]));
      dropped[i] = true;
      break;
    }
  }
  std::vector<Piece> kept;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (!dropped[i]) kept.push_back(std::move(pieces[i]));
  }
  return kept;
}

// Step 3: free air around the rig. The slab [r - c, r + c] along one of the object's own
// axes leaves every piece at least c from the rig along that axis, so at least c away.
std::vector<Piece> clearRig(std::vector<Piece> pieces, const Eigen::Vector3d& rig, const RoomModelCleanup& options,
                            std::vector<std::string>& notes) {
  const double clearance = options.rig_clearance_m;
  std::vector<Piece> kept;
  for (Piece& piece : pieces) {
    if (distanceToCuboid(piece.object, rig) >= clearance && !cuboidContains(piece.object, rig)) {
      kept.push_back(std::move(piece));
      continue;
    }
    const Eigen::Vector3d r = toCuboidFrame(piece.object, rig);
    const Bounds whole = boundsOf(piece.object);
    std::vector<Bounds> best;
    double best_removed = whole.volume() + 1.0;
    int best_axis = 0;
    for (int k = 0; k < 3; ++k) {
      Bounds below = whole, above = whole;
      below.hi[k] = std::min(whole.hi[k], r[k] - clearance);
      above.lo[k] = std::max(whole.lo[k], r[k] + clearance);
      std::vector<Bounds> parts;
      double kept_volume = 0.0;
      for (const Bounds& part : {below, above}) {
        if (part.hi[k] - part.lo[k] < std::max(options.min_object_size_m, kCrossingToleranceM)) continue;
        parts.push_back(part);
        kept_volume += part.volume();
      }
      const double removed = whole.volume() - kept_volume;
      if (removed < best_removed) {
        best_removed = removed;
        best = parts;
        best_axis = k;
      }
    }
    const std::string why = " to keep " + metres(clearance) + " of free air around the rig at " + pointText(rig);
    const std::string along = std::string(" along its own ") + kAxisNames[best_axis] + " axis";
    const std::string how_much = ": " + number(best_removed) + " of " + number(whole.volume()) + " m^3 removed";
    if (best.empty()) {
      notes.push_back(objectName(piece) + " dropped" + why + ": nothing of it lies " + metres(clearance) +
                      " or more from the rig");
    } else if (best.size() == 1) {
      notes.push_back(objectName(piece) + " cut back" + along + why + how_much);
    } else {
      notes.push_back(objectName(piece) + " split in two" + along + why + how_much);
    }
    for (const Bounds& part : best) kept.push_back({withBounds(piece.object, part), piece.original});
  }
  return kept;
}

}  // namespace

std::vector<std::string> cleanUpRoomModel(RoomModel& model, const RoomModelCleanup& options) {
  checkInput(model, options);
  std::vector<std::string> notes;
  std::vector<Piece> pieces = cutAllToBox(model, options, notes);
  pieces = dropHidden(std::move(pieces), options, notes);
  const Eigen::Vector3d& rig = model.rig_position_m;
  if ((rig.array() > 0.0).all() && (rig.array() < model.size_m.array()).all()) {
    pieces = clearRig(std::move(pieces), rig, options, notes);
  } else {
    notes.push_back("the rig at " + pointText(rig) + " is outside the room box [0, " + number(model.size_m.x()) +
                    "] x [0, " + number(model.size_m.y()) + "] x [0, " + number(model.size_m.z()) +
                    "] m: it cannot be the listener");
  }
  model.objects.clear();
  for (Piece& piece : pieces) model.objects.push_back(std::move(piece.object));
  return notes;
}

}  // namespace room_reverb::core
