#pragma once
// Direction of arrival of a first-order B-format (AmbiX: ACN W, Y, Z, X; SN3D, so a plane
// wave from unit direction u gives X, Y, Z = u W) segment, after Remaggi et al. section
// 2.1: steer a virtual cardioid S(v, n) = 1/2 [W(n) + v . (X(n), Y(n), Z(n))] and take the
// direction v of largest energy sum_n S(v, n)^2.
//
// That energy is a quadratic form in v: E(v) = 1/4 [Eww + 2 v.p + v^T R v] with
// Eww = sum W^2, p = sum W (X, Y, Z), R = sum (X, Y, Z)(X, Y, Z)^T over the (windowed)
// segment. Both searches below work on these statistics: the grid evaluates E on a
// near-uniform sphere grid as the paper does; the closed form maximises E on the unit
// sphere exactly through the Lagrange (secular) equation.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/rsao/analysis_window.h"

namespace room_reverb::core {

struct CardioidSteeringStatistics {
  double energy_w = 0.0;                                // Eww
  Eigen::Vector3d w_cross = Eigen::Vector3d::Zero();    // p, in room axes (x, y, z)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // R, in room axes

  // E(v) = 1/4 [Eww + 2 v.p + v^T R v]: the steered cardioid's energy towards v.
  double steeredEnergy(const Eigen::Vector3d& v) const;

  // How much of the segment arrives as one plane wave: 1 minus the diffuseness of DirAC
  // (Pulkki 2007), 2 |p| / (Eww + tr R) in SN3D. 1 for a single plane wave (X, Y, Z = u W,
  // so |p| = tr R = Eww); 0 for an isotropic diffuse field (p = 0); in between for two
  // arrivals from different directions, or one on a diffuse background. 0 for silence.
  double directness() const;
};

// Statistics of the windowed segment (samples times weights) of a first-order AmbiX
// buffer. InputError for fewer than 4 channels.
CardioidSteeringStatistics steeringStatistics(const AudioBuffer& ambix, const SampleWindow& window);

// sum_n S(v, n)^2 computed sample by sample: the paper's definition, which the quadratic
// form equals (kept for the tests and as the reference of that identity).
double steeredCardioidEnergy(const AudioBuffer& ambix, const SampleWindow& window, const Eigen::Vector3d& v);

struct DirectionOfArrival {
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit, towards where the sound comes from
  double azimuth_rad = 0.0;    // counter-clockwise from +x, [-pi, pi)
  double elevation_rad = 0.0;  // up from the horizontal plane, [-pi/2, pi/2]
  double steered_energy = 0.0;  // E at the direction
};

// Azimuth and elevation (DESIGN.md conventions) of a non-zero vector.
DirectionOfArrival directionFromVector(const Eigen::Vector3d& v);

// A near-uniform sphere grid (the Fibonacci lattice) with about one point per step^2 of
// solid angle: ceil(4 pi / step^2) points (41 253 for 1 degree). Neighbouring points are
// about `step_rad` apart. InputError for a step outside (0, pi/4].
std::vector<Eigen::Vector3d> sphereGrid(double step_rad);

// The grid point of largest E (the paper's search). Cost: one quadratic form per point.
DirectionOfArrival directionByGridSearch(const CardioidSteeringStatistics& stats, double grid_step_rad);

// The exact maximiser of E on the unit sphere. Stationary points satisfy (lambda I - R) v = p;
// the maximum is the one with lambda >= the largest eigenvalue mu_max of R, where
// v = sum_i c_i / (lambda - mu_i) q_i (R = Q diag(mu) Q^T, c = Q^T p) and lambda solves the
// secular equation sum_i c_i^2 / (lambda - mu_i)^2 = 1, which has exactly one root in
// [mu_max + |c_max|, mu_max + |p|] (found by safeguarded Newton). When p has (next to) no
// part along q_max and the other parts give ||v|| < 1 at lambda = mu_max (the "hard
// case"), lambda = mu_max and the missing length is taken along q_max.
DirectionOfArrival directionClosedForm(const CardioidSteeringStatistics& stats);

}  // namespace room_reverb::core
