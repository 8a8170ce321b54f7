#pragma once
// Rooms as real captures show them, for the visual route's tests and its accuracy report:
// walls that are not one plane (recessed doors and windows, radiators, skirting), runs of
// kitchen units along a wall (base cabinets, worktops, wall units, a tall fridge),
// shelving full of clutter, wardrobes, sofas, tables with chairs, ceiling lights hanging
// below the ceiling, each with a plausible library material so that renderCapture
// (capture_generator.h) can photograph it. Each room comes with its truth: the box of its main wall planes (what
// the paper's Table 1 measures) and the furniture a user would name.
//
// Three families of rooms from disjoint seeds: `kDevelopment` rooms are the ones the fit's
// parameters may be tuned on; `kHeldOut` rooms (larger and narrower rooms, higher ceilings,
// deeper recesses, more clutter) are only ever reported; `kDevelopmentLarge` rooms are
// drawn from the held-out set's ranges with seeds of their own, to tune on what only large
// rooms show (faces of more than a hundred material patches).
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core {

enum class ClutterSet { kDevelopment, kHeldOut, kDevelopmentLarge };

struct ClutteredRoom {
  std::string name;
  // What the rig sees: the box pushed out where a wall has a recess, the wall pieces
  // around the recess as cuboids, fixtures and furniture as cuboids.
  RoomModel scanned;
  // The truth: the box of the main wall planes, in the same room frame (origin at the main
  // walls' corner), the same rig pose; objects are the furniture (not the wall pieces,
  // radiators and skirting).
  RoomModel truth;
  // Which walls (kRoomSurfaceNames index 2..5) have a recess, a run of units, shelving.
  // The glass of each window recess (label "window", glass_window), in the scanned room's
  // frame and not among its objects: added to it with CameraImperfections::emitter_labels
  // {"window"}, a window shows daylight, as a camera exposed for the room records it.
  std::vector<CuboidObject> window_panes;
  std::vector<int> recessed_walls;
  std::vector<int> furnished_walls;
};

// One room of the set; `index` picks the seed (no two sets share one).
ClutteredRoom clutteredRoom(ClutterSet set, int index);

}  // namespace room_reverb::core
