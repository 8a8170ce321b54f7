#pragma once
// The low band by the wave equation: the standard leapfrog scheme (the 7-point
// finite-difference time-domain scheme; Botteldooren 1995, Bilbao 2009) on the room's
// voxel grid (fdtd_grid.h), at its stability limit, Courant number lambda = c dt / h =
// 1/sqrt(3), where the update is p+ = (1/3) (sum of the six neighbours) - p-.
//
// Walls: an air cell with K air neighbours and boundary faces of specific admittance
// beta_f follows the finite-volume form
//   (1 + g) p+ = (2 - K lambda^2) p + lambda^2 (sum of its K air neighbours) - (1 - g) p-,
//   g = (lambda / 2) sum_f beta_f,
// which is passive for every beta >= 0 (a locally reacting boundary with frequency-
// independent admittance; Kowalczyk and van Walstijn 2011 derive the same for planar
// walls). One run serves one set of admittances: the low band runs once per octave with
// that octave's admittances (boundary_admittance.h).
//
// Dispersion: the scheme's waves travel slower than c, most along the grid's axes, where
// at N cells per wavelength the phase speed is 2 asin(lambda sin(pi / N)) / (2 pi lambda
// / N) times c: 1.1 % slow at 10 cells (the default at the band's top), 0.27 % at 20;
// along the cube diagonal it is exact.
//
// Source and receiver: a unit-area impulse injected at the source with trilinear weights
// on the eight cells around it, scaled so that the free-field response is A(t - r/c) / r
// (the convention of the image sources: gain 1 at 1 m); pressure and its gradient read
// at the listener with trilinear weights. The gradient integrated over time gives the
// particle velocity, and -rho c v the first-order AmbiX channels (SN3D): a plane wave
// from direction d gives X, Y, Z = p d.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/fdtd_grid.h"

namespace room_reverb::core {

struct FdtdOptions {
  double duration_s = 1.0;
  double speed_of_sound_m_s = 343.0;
  int threads = 0;  // 0: all hardware threads
};

struct FdtdResponse {
  double sample_rate_hz = 0.0;  // 1 / dt = c sqrt(3) / h
  // Per time step: the response at the listener to a unit-area impulse of the source, so
  // that sum(pressure) dt over the direct sound is 1 / r. W = pressure; X, Y, Z the
  // first-order channels as the header says.
  std::vector<double> pressure;
  std::array<std::vector<double>, 3> velocity;
  std::size_t steps = 0;
  std::size_t air_cells = 0;
};

// The grid spacing that gives `cells_per_wavelength` cells per wavelength at
// `max_frequency_hz`.
double fdtdSpacingFor(double max_frequency_hz, double cells_per_wavelength, double speed_of_sound_m_s);

// The phase speed over c of the scheme's waves along a grid axis at `cells_per_wavelength`.
double fdtdAxialPhaseSpeedRatio(double cells_per_wavelength);

// Runs the scheme on `grid` with `face_admittance[m]` the specific admittance of scene
// material m. Throws InputError when the source or listener cell (and its trilinear
// neighbours) are not all air, for a negative or non-finite admittance, or a material
// index out of range.
FdtdResponse solveWaveField(const FdtdGrid& grid, const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                            const std::vector<double>& face_admittance, const FdtdOptions& options);

}  // namespace room_reverb::core
