#pragma once
// A fitted room model made simulable by construction. The layout fit leaves what a point
// cloud gives: cuboids that reach through a wall, slivers, objects hidden inside others,
// and now and then a cuboid (a kitchen run seen as one cabinet) that holds the rig itself,
// where the listener must stand. This cuts the objects back to the room box, drops what
// is left too thin or hidden, and clears free air around the rig.
//
// Objects that only touch, or partly overlap, are left as they are: the simulator decides
// inside and outside from the model's solids (room_shape.h), for which touching and
// overlapping are exact, and a cuboid around two overlapping ones would add solid that is
// not there.
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core {

struct RoomModelCleanup {
  // Free air kept around model.rig_position_m [m]: no object nearer than this.
  double rig_clearance_m = 0.3;
  // An object that a cut leaves thinner than this [m] along a side it shortened is
  // dropped (a sliver); one fitted thin, a worktop, is left.
  double min_object_size_m = 0.05;
  // An object with at least this fraction of its volume inside one other object is
  // dropped: no sound reaches it, and its faces would only add to the room's surface.
  double hidden_fraction = 0.9;
};

// Changes `model` in place, in this order:
//  1. Every object is cut back to the room box (not above the walls' top when the room has
//     no ceiling). An upright object turned by a yaw is cut along its own axis most nearly
//     normal to the wall it crosses, until its deepest corner touches the wall: it stays a
//     cuboid with the same yaw, entirely inside, and loses at most the wedge between the
//     cut and the wall. Objects the cut leaves thinner than min_object_size_m (or that
//     lie wholly outside) are dropped.
//  2. Objects at least hidden_fraction inside a larger one (or an equal one listed
//     earlier) are dropped.
//  3. An object nearer the rig than rig_clearance_m loses the slab 2 * rig_clearance_m
//     thick around the rig, along whichever of its own axes removes the least volume: a cut
//     where the rig is near its end, a split in two (same label and material) where the
//     rig is in its middle. A piece thinner than min_object_size_m goes with the slab; an
//     object with nothing left is dropped, said so.
// Returns one line per change, for the caller to print as warnings. Objects are numbered
// as in the model as given, from 0. A rig outside the room box is reported, not moved.
// Throws InputError for options out of range or a room box without positive size.
std::vector<std::string> cleanUpRoomModel(RoomModel& model, const RoomModelCleanup& options = {});

}  // namespace room_reverb::core
