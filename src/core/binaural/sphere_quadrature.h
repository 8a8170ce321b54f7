#pragma once
// Quadrature weights for directions that sample the sphere unevenly (private to
// src/core/binaural).
#include <Eigen/Core>
#include <vector>

namespace room_reverb::core {

// One weight per direction, summing to one, proportional to the inverse of the local
// sampling density: a von Mises-Fisher kernel density estimate whose width is twice the
// mean point spacing sqrt(4 pi / n). Near-uniform sets (Lebedev, Fibonacci, t-designs) get
// near-equal weights; sets that crowd the horizontal plane or thin out below the head get
// weights that stop the crowded regions from dominating a least-squares fit. (Exact
// Voronoi areas would need a spherical hull; the kernel estimate is smooth and cheap.)
Eigen::VectorXd densityCompensatingWeights(const std::vector<Eigen::Vector3d>& directions);

}  // namespace room_reverb::core
