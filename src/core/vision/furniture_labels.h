#pragma once
// Furniture names from a cuboid's size alone (no appearance): a first guess that a later
// classifier on the colours may replace.
#include <string>

#include "room_reverb/acoustics/room_model.h"

namespace room_reverb::core::layout {

// `box` in the room frame with size.x >= size.y; `floor_standing` if its bottom is on the
// floor; `against_wall` if a long side touches a wall. First rule that fits, with L, W the
// long and short plan sides and H the top's height above the floor (metres):
//   not on the floor:                              shelf if against a wall, else object
//   H >= 1.3:                                      shelf if W <= 0.4, else cabinet
//   0.3 <= H < 0.65, L >= 1.8 and W >= 0.9:        bed
//   0.65 <= H < 1.1, L >= 1.4 and W >= 0.7:        sofa   (a 2 m x 0.9 m table is called a sofa too)
//   H >= 0.9:                                      chair if L <= 0.7, else cabinet (sideboard, counter)
//   H >= 0.6:                                      chair if L <= 0.7, desk if against a wall and
//                                                  W <= 0.9, else table
//   H >= 0.3:                                      sofa if L >= 1.4 and W >= 0.6 (a low one),
//                                                  box if L <= 0.6, else table (coffee table)
//   otherwise:                                     box
std::string furnitureLabel(const CuboidObject& box, bool floor_standing, bool against_wall);

}  // namespace room_reverb::core::layout
