#pragma once
// Real spherical harmonics in the AmbiX convention: ACN order (index l^2 + l + m), SN3D
// normalisation, no Condon-Shortley phase.
#include <Eigen/Core>
#include <vector>

namespace room_reverb::core {

constexpr int kMaxAmbisonicOrder = 3;

inline int ambisonicChannelCount(int order) { return (order + 1) * (order + 1); }

// The (order+1)^2 harmonics of a direction (unit vector, room or head frame). Order 0..3.
std::vector<double> sn3dHarmonics(int order, const Eigen::Vector3d& direction);
// The same into `y`, resized to (order+1)^2: no allocation once it has that size (the
// renderer's moving taps ask for every tap's harmonics every block, on the audio thread).
void sn3dHarmonicsInto(int order, const Eigen::Vector3d& direction, std::vector<double>& y);

}  // namespace room_reverb::core
