// The wave solver against what the wave equation says: the free-field level, delay and
// direction of a point source, the modes of a rigid box, passivity of the walls, and the
// admittance that gives a random-incidence absorption.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/boundary_admittance.h"
#include "room_reverb/acoustics/fdtd_grid.h"
#include "room_reverb/acoustics/fdtd_solver.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/common/error.h"
#include "shoebox.h"

using namespace room_reverb::core;

namespace {

constexpr double kC = 343.0;

AcousticScene boxScene(const Eigen::Vector3d& size) {
  return AcousticScene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.0, 0.0));
}

FdtdOptions options(double duration_s) {
  FdtdOptions o;
  o.duration_s = duration_s;
  o.speed_of_sound_m_s = kC;
  o.threads = 2;
  return o;
}

// |DFT| of `x` (Hann window) at `f`.
double magnitudeAt(const std::vector<double>& x, double sample_rate_hz, double f) {
  std::complex<double> sum = 0.0;
  const double n = static_cast<double>(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double window = 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(k) / n);
    sum += window * x[k] * std::polar(1.0, -2.0 * M_PI * f * static_cast<double>(k) / sample_rate_hz);
  }
  return std::abs(sum);
}

double peakNear(const std::vector<double>& x, double sample_rate_hz, double f0, double span_hz) {
  double best_f = f0, best = -1.0;
  for (double f = f0 - span_hz; f <= f0 + span_hz; f += 0.02) {
    const double m = magnitudeAt(x, sample_rate_hz, f);
    if (m > best) {
      best = m;
      best_f = f;
    }
  }
  return best_f;
}

}  // namespace

TEST(BoundaryAdmittance, TheAdmittanceGivesTheAbsorptionItWasAskedFor) {
  // A nearly hard wall absorbs 8 beta (the integral of 8 beta sin(theta)).
  EXPECT_NEAR(randomIncidenceAbsorption(0.001), 0.008, 0.0002);
  EXPECT_NEAR(randomIncidenceAbsorption(kAdmittanceOfMaxAbsorption), 0.9512, 0.0002);
  double previous = 0.0;
  for (double alpha : {0.01, 0.05, 0.2, 0.5, 0.8, 0.95}) {
    const double beta = admittanceForRandomIncidenceAbsorption(alpha);
    EXPECT_NEAR(randomIncidenceAbsorption(beta), alpha, 1e-9) << alpha;
    EXPECT_GT(beta, previous);
    previous = beta;
  }
  EXPECT_DOUBLE_EQ(admittanceForRandomIncidenceAbsorption(0.99), kAdmittanceOfMaxAbsorption);
  EXPECT_DOUBLE_EQ(admittanceForRandomIncidenceAbsorption(0.0), 0.0);
}

TEST(FdtdGrid, AnAlignedBoxIsItsCellsExactly) {
  const AcousticScene scene = boxScene({2.0, 1.5, 1.2});
  const FdtdGrid grid = voxelizeScene(scene, 0.1);
  EXPECT_EQ(grid.airCellCount(), 20u * 15u * 12u);
  EXPECT_NEAR(grid.boundaryFaceAreaM2(), 2.0 * (2.0 * 1.5 + 2.0 * 1.2 + 1.5 * 1.2), 1e-9);
  for (const FdtdGrid::BoundaryCell& cell : grid.boundary) {
    for (int m : cell.face_material) EXPECT_LE(m, 0);
  }
  EXPECT_THROW(voxelizeScene(scene, 0.0), InputError);
  EXPECT_THROW(voxelizeScene(scene, 1e-5), InputError);  // 3.6e15 cells
}

TEST(FdtdSolver, APointSourceInFreeFieldArrivesAtOneOverRFromItsDirection) {
  // A 4 m cube, source and listener near its centre 1.1 m apart: the direct sound is
  // over before the first reflection (at least 3.9 m of path) arrives.
  const AcousticScene scene = boxScene({4.0, 4.0, 4.0});
  const FdtdGrid grid = voxelizeScene(scene, 0.1);
  const Eigen::Vector3d source(2.03, 1.96, 2.01);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.6, -0.5, 0.62).normalized();  // from the listener to the source
  const double r = 1.1;
  const Eigen::Vector3d listener = source - r * direction;
  const FdtdResponse response = solveWaveField(grid, source, listener, {0.0}, options(0.012));
  const double dt = 1.0 / response.sample_rate_hz;
  const std::size_t end = static_cast<std::size_t>(3.0 / kC / dt);
  double area = 0.0, moment = 0.0;
  Eigen::Vector3d first_order = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < end; ++n) {
    area += response.pressure[n] * dt;
    moment += response.pressure[n] * dt * static_cast<double>(n) * dt;
  }
  EXPECT_NEAR(area, 1.0 / r, 0.02 / r);
  EXPECT_NEAR(moment / area, r / kC, dt);
  // A spherical wave's particle velocity, near field included, is radial: every time
  // integral of X, Y, Z points from the listener to the source.
  double w = 0.0;
  for (std::size_t n = 0; n < end; ++n) w += response.pressure[n];
  for (int axis = 0; axis < 3; ++axis) {
    double x = 0.0;
    for (std::size_t n = 0; n < end; ++n) x += response.velocity[static_cast<std::size_t>(axis)][n];
    first_order[axis] = x;
  }
  const Eigen::Vector3d measured = first_order / first_order.norm();
  EXPECT_GT(measured.dot(direction), std::cos(3.0 * M_PI / 180.0)) << measured.transpose();
  EXPECT_GT(w, 0.0);
}

TEST(FdtdSolver, ARigidBoxRingsAtItsModes) {
  const Eigen::Vector3d size(2.0, 1.5, 1.1);
  const AcousticScene scene = boxScene(size);
  const FdtdGrid grid = voxelizeScene(scene, 0.05);
  const FdtdResponse response = solveWaveField(grid, {0.23, 0.31, 0.27}, {1.71, 1.18, 0.84}, {0.0}, options(1.0));
  for (const Eigen::Vector3i& mode : {Eigen::Vector3i(1, 0, 0), Eigen::Vector3i(0, 1, 0), Eigen::Vector3i(0, 0, 1),
                                     Eigen::Vector3i(1, 1, 1), Eigen::Vector3i(2, 0, 0)}) {
    const double analytic = 0.5 * kC * (mode.cast<double>().array() / size.array()).matrix().norm();
    const double measured = peakNear(response.pressure, response.sample_rate_hz, analytic, 2.5);
    // The scheme's dispersion at these wavelengths is below 0.03 %; the window and the
    // 0.02 Hz search step bound the rest.
    EXPECT_NEAR(measured, analytic, 0.15) << mode.transpose();
  }
}

TEST(FdtdSolver, AbsorbingWallsOnlyTakeEnergyAndRigidOnesKeepIt) {
  const AcousticScene scene = boxScene({1.6, 1.2, 1.0});
  const FdtdGrid grid = voxelizeScene(scene, 0.08);
  // The unit-area impulse leaves a closed room a static pressure (a volume was pushed
  // into it) that no wall admittance takes away; the second difference sees past it.
  auto windowEnergy = [](const std::vector<double>& p, std::size_t from, std::size_t to) {
    double e = 0.0;
    for (std::size_t n = std::max<std::size_t>(from, 1); n < to; ++n) {
      const double d2 = p[n + 1] - 2.0 * p[n] + p[n - 1];
      e += d2 * d2;
    }
    return e;
  };
  const FdtdResponse rigid = solveWaveField(grid, {0.4, 0.3, 0.35}, {1.1, 0.8, 0.6}, {0.0}, options(1.0));
  const FdtdResponse lossy = solveWaveField(grid, {0.4, 0.3, 0.35}, {1.1, 0.8, 0.6},
                                            {admittanceForRandomIncidenceAbsorption(0.2)}, options(1.0));
  const std::size_t tenth = rigid.steps / 10;
  for (const FdtdResponse* r : {&rigid, &lossy}) {
    for (double v : r->pressure) ASSERT_TRUE(std::isfinite(v));
  }
  const double rigid_first = windowEnergy(rigid.pressure, tenth, 2 * tenth);
  const double rigid_last = windowEnergy(rigid.pressure, 9 * tenth, 10 * tenth);
  EXPECT_NEAR(rigid_last / rigid_first, 1.0, 0.5);  // no loss, no growth (modes beat)
  double previous = windowEnergy(lossy.pressure, tenth, 2 * tenth);
  for (std::size_t w = 2; w < 10; ++w) {
    const double e = windowEnergy(lossy.pressure, w * tenth, (w + 1) * tenth);
    EXPECT_LT(e, previous) << w;
    previous = e;
  }
}

// A 4 m duct 0.3 m across, rigid but for its two ends: in the 250 Hz octave (below the
// duct's first cross mode, 572 Hz) the sound runs as a plane wave between the ends, and
// its energy falls by R^2 = ((1 - beta) / (1 + beta))^2 each L / c.
TEST(FdtdSolver, APlaneWaveBetweenTwoAbsorbingEndsDecaysByTheirReflectionFactor) {
  const double length = 4.0;
  TriangleMesh mesh = room_reverb::test::shoeboxMesh({length, 0.3, 0.3});
  mesh.material_names.push_back("end");
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (std::abs(mesh.normal(t).x()) > 0.9) mesh.triangle_material[t] = 1;
  }
  MaterialLibrary library = room_reverb::test::uniformLibrary(0.0, 0.0);
  AcousticMaterial end;
  end.name = "end";
  end.source = "test";
  library.add(end);
  const FdtdGrid grid = voxelizeScene(AcousticScene(mesh, library), 0.03);
  for (double beta : {0.05, 0.2}) {
    const FdtdResponse response = solveWaveField(grid, {0.51, 0.15, 0.15}, {2.93, 0.16, 0.14}, {0.0, beta}, options(1.0));
    const BandFilterBank bank(standardBands(BandResolution::kOctave), response.sample_rate_hz);
    const std::vector<float> band = bank.extract(bank.analyse(std::vector<float>(response.pressure.begin(), response.pressure.end())), 2);
    const double reflection = (1.0 - beta) / (1.0 + beta);
    const double expected_db_per_s = 20.0 * std::log10(reflection) * kC / length;
    // Fit the level over 40 dB of the expected decay, in ten windows, from 30 ms.
    const double dt = 1.0 / response.sample_rate_hz;
    const double span = 40.0 / -expected_db_per_s, step = span / 10.0;
    double st = 0.0, sl = 0.0, stt = 0.0, stl = 0.0;
    for (int w = 0; w < 10; ++w) {
      const double from = 0.03 + w * step;
      double energy = 0.0;
      for (auto n = static_cast<std::size_t>(from / dt); n < static_cast<std::size_t>((from + step) / dt); ++n) energy += band[n] * band[n];
      const double t = from + 0.5 * step, level = 10.0 * std::log10(energy);
      st += t;
      sl += level;
      stt += t * t;
      stl += t * level;
    }
    const double slope = (10.0 * stl - st * sl) / (10.0 * stt - st * st);
    EXPECT_NEAR(slope / expected_db_per_s, 1.0, 0.05) << "beta " << beta << ": " << slope << " dB/s";
  }
}

TEST(FdtdSolver, DispersionIsWhatTheSchemeSays) {
  EXPECT_NEAR(fdtdAxialPhaseSpeedRatio(10.0), 0.9891, 0.0002);
  EXPECT_GT(fdtdAxialPhaseSpeedRatio(20.0), 0.996);
  EXPECT_NEAR(fdtdSpacingFor(500.0, 10.0, kC), 0.0686, 1e-12);
}

TEST(FdtdSolver, BadInputIsAnInputError) {
  const AcousticScene scene = boxScene({2.0, 1.5, 1.2});
  const FdtdGrid grid = voxelizeScene(scene, 0.1);
  EXPECT_THROW(solveWaveField(grid, {0.02, 0.7, 0.6}, {1.5, 0.7, 0.6}, {0.0}, options(0.1)), InputError);
  EXPECT_THROW(solveWaveField(grid, {0.5, 0.7, 0.6}, {5.0, 0.7, 0.6}, {0.0}, options(0.1)), InputError);
  // The listener's gradient needs air one cell further.
  EXPECT_THROW(solveWaveField(grid, {0.5, 0.7, 0.6}, {1.88, 0.7, 0.6}, {0.0}, options(0.1)), InputError);
  EXPECT_THROW(solveWaveField(grid, {0.5, 0.7, 0.6}, {1.5, 0.7, 0.6}, {-0.1}, options(0.1)), InputError);
  EXPECT_THROW(solveWaveField(grid, {0.5, 0.7, 0.6}, {1.5, 0.7, 0.6}, {}, options(0.1)), InputError);
  EXPECT_THROW(solveWaveField(grid, {0.5, 0.7, 0.6}, {1.5, 0.7, 0.6}, {0.0}, options(0.0)), InputError);
  EXPECT_THROW(fdtdSpacingFor(500.0, 1.0, kC), InputError);
}
