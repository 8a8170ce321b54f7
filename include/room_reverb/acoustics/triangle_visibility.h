#pragma once
// Which triangles of a mesh a point sees whole. The ray tracer's diffuse rain sends each
// scattered reflection straight to the listener when the listener sees the wall point;
// asking Embree for every reflection is a second ray per bounce (about 7 % of the
// accurate BRAS CR2 pair's time, docs/simulation.md). For a triangle that no other triangle can hide from the listener
// the answer is yes wherever on it the reflection lands, so the ray is not needed.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "room_reverb/acoustics/triangle_mesh.h"

namespace room_reverb::core {

// Per triangle: true when no other triangle enters the pyramid from `point` to it (a
// separating-axis test of the pyramid against each other triangle; triangles that only
// touch it, such as its neighbours across an edge that folds away from the point, do not
// hide it), and `point` is at least 1 um off its plane. False for every triangle of a
// mesh with more than `max_triangles` (the test is quadratic in the count): there each
// ray decides.
std::vector<bool> trianglesSeenWhole(const TriangleMesh& mesh, const Eigen::Vector3d& point,
                                     std::size_t max_triangles = 4096);

}  // namespace room_reverb::core
