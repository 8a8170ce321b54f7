#pragma once
// Virtual loudspeaker layouts for the virtual-loudspeaker binaural decoder: named
// direction sets, and layouts given as azimuth/elevation lists in degrees (configuration
// files state angles in degrees, DESIGN.md conventions; the code works on unit vectors in
// the `head` frame).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace room_reverb::core {

// The paper's layout, exactly as the paper states it: 24 loudspeakers on the horizontal
// ring, 12 at +30 deg and 12 at -30 deg elevation, each ring equally spaced in azimuth
// starting at 0 deg. It leaves both poles empty (nothing above 30 deg or below -30 deg),
// so a mode-matching decoder of order 3 cannot reproduce the (l, m = 0) harmonics' full
// elevation dependence on it: three elevations cannot match four zonal harmonics.
std::vector<Eigen::Vector3d> paperRingsLayout();

// `count` points of the spherical Fibonacci lattice (equal-area rings in z, successive
// points turned by the golden angle; Gonzalez, "Measurement of areas on a sphere using
// Fibonacci and latitude-longitude lattices", Math. Geosci. 2010): near-uniform for any
// count, which a t-design is not. InputError unless 21 <= count <= 10000.
std::vector<Eigen::Vector3d> fibonacciLayout(std::size_t count);

// The default virtual layout, "fibonacci_50". Why: a mode-matching decoder needs the
// layout's harmonic matrix to be well conditioned up to order 3; 50 near-uniform points,
// about three per order-3 channel, keep its condition number at 2.8 (1.7 at order 1; the
// paper's rings: 5.9 at order 2, singular at order 3). The 240-point 21-design would do
// as well but needs a 720-number table; the 50-point Lebedev rule is exact only with
// unequal weights, which a plain mode-matching decoder ignores.
constexpr const char* kDefaultLoudspeakerLayout = "fibonacci_50";

// "paper_rings" or "fibonacci_<count>" (case-sensitive). InputError otherwise.
std::vector<Eigen::Vector3d> loudspeakerLayoutByName(const std::string& name);

// Directions from {azimuth, elevation} pairs in degrees (azimuth counter-clockwise from
// ahead, elevation up). InputError for an empty list, a non-finite angle, an elevation
// outside [-90, 90], or two loudspeakers less than 0.1 deg apart.
std::vector<Eigen::Vector3d> loudspeakerLayoutFromDegrees(
    const std::vector<std::array<double, 2>>& azimuth_elevation_deg);

// A layout name, or an explicit list "az,el; az,el; ..." in degrees.
std::vector<Eigen::Vector3d> parseLoudspeakerLayout(const std::string& text);

}  // namespace room_reverb::core
