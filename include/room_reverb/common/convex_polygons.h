#pragma once
// Polygons in a plane, as upright cuboids' footprints seen from above: area, clipping by a
// convex polygon, and the area of a union. The overlap and free-volume sums of the room
// model's objects are built on these.
#include <Eigen/Core>
#include <vector>

namespace room_reverb::core {

using Polygon2d = std::vector<Eigen::Vector2d>;  // vertices counter-clockwise

// Area enclosed (the absolute value of the shoelace sum).
double polygonArea(const Polygon2d& polygon);

// The part of `subject` inside the convex, counter-clockwise `clip` (Sutherland-Hodgman:
// exact when `subject` is convex too). Empty when they do not overlap.
Polygon2d clipToConvex(Polygon2d subject, const Polygon2d& clip);

// Area covered by at least one of the counter-clockwise polygons, exact whether they are
// apart, touch along an edge or overlap: each edge counts the parts of it no other polygon
// covers (an edge shared in the same direction counts once, in opposite directions the
// two cancel). Vertices within 1e-9 m of another polygon's edge line count as on it.
double unionArea(const std::vector<Polygon2d>& polygons);

}  // namespace room_reverb::core
