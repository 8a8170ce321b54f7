// The wave solver's low band joined to the geometric response: where the two should agree
// (a diffuse box: level in the overlap band, decay), what the join leaves alone (the high
// bands, the higher-order channels), and bad settings.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <iostream>
#include <optional>

#include "room_reverb/acoustics/fdtd_grid.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/acoustics/impulse_response_synthesis.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/acoustics/wave_low_band.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/common/error.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"
#include "shoebox.h"

using namespace room_reverb::core;
using room_reverb::test::noAir;

namespace {

SimulationSettings boxSettings() {
  SimulationSettings settings;
  settings.air = noAir();
  settings.duration_s = 1.2;
  settings.ambisonic_order = 1;
  settings.rays.ray_count = 20000;
  settings.rays.threads = 2;
  settings.wave.crossover_hz = 250.0;
  return settings;
}

double bandEnergyOf(const std::vector<float>& signal, std::size_t band) {
  const BandFilterBank bank(standardBands(BandResolution::kOctave), kInternalSampleRateHz);
  double e = 0.0;
  for (float v : bank.extract(bank.analyse(signal), band)) e += static_cast<double>(v) * v;
  return e;
}

const Eigen::Vector3d kSource(1.5, 1.2, 1.4), kListener(4.3, 2.9, 1.6);

// The same room simulated with the geometric low band and with the wave one.
struct BothLowBands {
  SimulationResult geometric, wave;
};
BothLowBands simulateBothLowBands(const AcousticScene& scene, const Eigen::Vector3d& source,
                                  const Eigen::Vector3d& listener, SimulationSettings settings) {
  BothLowBands out;
  settings.low_band = LowBandMethod::kGeometric;
  out.geometric = simulateRoom(scene, source, listener, settings);
  settings.low_band = LowBandMethod::kWave;
  out.wave = simulateRoom(scene, source, listener, settings);
  return out;
}

}  // namespace

// In a rigid box the image sources are the exact solution of the wave equation for the
// pressure: over the first 25 ms (every path there is of order 4 or less, and the image
// sources go to order 6) the wave solver's W must carry the same energy per octave. X, Y
// and Z differ by more: the image sources encode each arrival as a plane wave, the solver
// has the true particle velocity with its near field. At 20 cells per wavelength; at the
// default 10 the 250 Hz octave comes out 0.9 dB low (its top, 354 Hz, has 7 cells per
// wavelength, and the waves along the axes are 2.3 % slow there).
TEST(WaveLowBand, InARigidBoxTheWavesCarryTheImageSourcesEnergy) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({6.0, 4.0, 3.0}), room_reverb::test::uniformLibrary(0.0, 0.0));
  SimulationSettings settings = boxSettings();
  settings.duration_s = 0.1;
  settings.image_source_order = 6;
  settings.rays.ray_count = 1000;
  settings.wave.cells_per_wavelength = 20.0;
  const WaveLowBand wave = simulateWaveLowBand(scene, kSource, kListener, 343.0, 0.1, settings.wave);
  EXPECT_TRUE(wave.stats.used);
  EXPECT_EQ(wave.stats.solver_runs, 3u);  // 63, 125, 250 Hz
  ASSERT_EQ(wave.response.channels.size(), 4u);
  ASSERT_EQ(wave.response.channels[0].size(), 4800u);
  ImageSourceOptions images;
  images.max_order = 6;
  SynthesisOptions synthesis;
  synthesis.duration_s = 0.1;
  synthesis.ambisonic_order = 1;
  // The same speed of sound on both sides.
  PropagationModel same = PropagationModel::from(noAir(), {});
  same.speed_of_sound_m_s = 343.0;
  synthesis.speed_of_sound_m_s = 343.0;
  const AudioBuffer exact = synthesizeImpulseResponse(computeImageSources(scene, kSource, kListener, same, images), nullptr, synthesis);
  const std::size_t window = 1200;  // 25 ms
  for (std::size_t band = 1; band <= 2; ++band) {
    for (std::size_t c = 0; c < 4; ++c) {
      std::vector<float> a(exact.channels[c].begin(), exact.channels[c].begin() + 4800);
      std::vector<float> b = wave.response.channels[c];
      a.resize(window + 240);  // the band filters' smear, 5 ms
      b.resize(window + 240);
      const double db = 10.0 * std::log10(bandEnergyOf(b, band) / bandEnergyOf(a, band));
      std::cout << "[ measured ] " << (band == 1 ? 125 : 250) << " Hz channel " << c << ": wave - image sources " << db << " dB\n";
      EXPECT_NEAR(db, 0.0, c == 0 ? 0.3 : 1.0) << band << " " << c;
    }
  }
}

// The join: above the crossover's width the response is the geometric one in every
// channel, and the stats say what was done.
TEST(WaveLowBand, AboveTheCrossoverTheResponseIsTheGeometricOne) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({6.0, 4.0, 3.0}), room_reverb::test::uniformLibrary(0.15, 0.6));
  SimulationSettings settings = boxSettings();
  settings.duration_s = 0.6;
  const auto [geometric, wave] = simulateBothLowBands(scene, kSource, kListener, settings);
  EXPECT_FALSE(geometric.low_band.used);
  ASSERT_TRUE(wave.low_band.used);
  EXPECT_NEAR(wave.low_band.crossover_hz, 250.0, 1e-12);
  EXPECT_NEAR(wave.low_band.grid_spacing_m, wave.speed_of_sound_m_s / 2500.0, 1e-12);
  std::cout << "[ measured ] overlap level " << wave.low_band.overlap_level_db << " dB, " << wave.low_band.grid_cells
            << " cells, " << wave.low_band.seconds << " s\n";
  // A locally reacting wall of real admittance takes its random-incidence absorption
  // mostly near grazing incidence: the early reflections come back stronger than the
  // image sources' angle-free absorption lets them (docs/simulation.md).
  EXPECT_GT(wave.low_band.overlap_level_db, 0.0);
  EXPECT_LT(wave.low_band.overlap_level_db, 5.0);
  for (std::size_t c = 0; c < 4; ++c) {
    const double ratio = bandEnergyOf(wave.impulse_response.channels[c], 5) / bandEnergyOf(geometric.impulse_response.channels[c], 5);
    EXPECT_NEAR(10.0 * std::log10(ratio), 0.0, 0.01) << c;  // 2 kHz
  }
}

TEST(WaveLowBand, ChannelsAboveFirstOrderKeepTheGeometricResponse) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({3.0, 2.5, 2.4}), room_reverb::test::uniformLibrary(0.2, 0.5));
  SimulationSettings settings = boxSettings();
  settings.duration_s = 0.3;
  settings.ambisonic_order = 2;
  settings.rays.ray_count = 2000;
  const Eigen::Vector3d source(0.8, 0.7, 1.2), listener(2.1, 1.7, 1.3);
  const auto [geometric, wave] = simulateBothLowBands(scene, source, listener, settings);
  ASSERT_EQ(wave.impulse_response.channels.size(), 9u);
  for (std::size_t c = 4; c < 9; ++c) EXPECT_EQ(wave.impulse_response.channels[c], geometric.impulse_response.channels[c]) << c;
  EXPECT_NE(wave.impulse_response.channels[0], geometric.impulse_response.channels[0]);
}

TEST(WaveLowBand, BadSettingsAreClearErrors) {
  EXPECT_EQ(parseLowBandMethod("wave"), LowBandMethod::kWave);
  EXPECT_EQ(toString(parseLowBandMethod("geometric")), "geometric");
  EXPECT_THROW(parseLowBandMethod("fdtd"), InputError);
  const AcousticScene scene(room_reverb::test::shoeboxMesh({3.0, 2.5, 2.4}), room_reverb::test::uniformLibrary(0.2, 0.5));
  WaveLowBandOptions options;
  options.crossover_hz = 20.0;
  EXPECT_THROW(simulateWaveLowBand(scene, {1, 1, 1}, {2, 1.5, 1.2}, 343.0, 0.1, options), InputError);
  options.crossover_hz = 250.0;
  options.cells_per_wavelength = 2.0;
  EXPECT_THROW(simulateWaveLowBand(scene, {1, 1, 1}, {2, 1.5, 1.2}, 343.0, 0.1, options), InputError);
  options.cells_per_wavelength = 10.0;
  // 5 cm from a wall: inside the grid's first cell (13.7 cm at 250 Hz).
  try {
    simulateWaveLowBand(scene, {0.05, 1, 1}, {2, 1.5, 1.2}, 343.0, 0.1, options);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("source (0.05, 1, 1) m is within"), std::string::npos) << e.what();
  }
}

// A room turned against the grid becomes a staircase with more face area than its walls
// (130 m^2 for 108 at 30 degrees); the faces' area correction gives the walls their own
// area back, and the decay stays that of the room aligned with the grid. Measured: T20
// 3 %, 10 % and 8 % short at 63, 125 and 250 Hz with the correction (the staircase still
// scatters), 21 % short at 250 Hz without it.
TEST(WaveLowBand, ARoomTurnedAgainstTheGridDecaysAsWhenAligned) {
  const Eigen::Vector3d centre(3.0, 2.0, 1.5);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::array<std::optional<double>, 2> t125, t250;
  for (int turned = 0; turned < 2; ++turned) {
    TriangleMesh mesh = room_reverb::test::shoeboxMesh({6.0, 4.0, 3.0});
    auto place = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return turned ? Eigen::Vector3d(turn * (p - centre) + centre) : p; };
    for (Eigen::Vector3d& v : mesh.vertices) v = place(v);
    const AcousticScene scene(mesh, room_reverb::test::uniformLibrary(0.2, 0.5));
    WaveLowBandOptions options;
    options.crossover_hz = 250.0;
    options.threads = 2;
    const WaveLowBand wave = simulateWaveLowBand(scene, place(kSource), place(kListener), 343.0, 1.5, options);
    const FdtdGrid grid = voxelizeScene(scene, wave.stats.grid_spacing_m);
    EXPECT_NEAR(grid.correctedBoundaryAreaM2(), 108.0, 1.1) << turned;
    if (turned) {
      EXPECT_GT(grid.boundaryFaceAreaM2(), 125.0);
    }
    const MetricsReport metrics = computeRoomAcousticParameters(wave.response.channels[0], 48000.0);
    t125[turned] = metrics.bands[1].t20_s;
    t250[turned] = metrics.bands[2].t20_s;
    ASSERT_TRUE(t125[turned] && t250[turned]) << metrics.bands[1].reason << metrics.bands[2].reason;
  }
  EXPECT_NEAR(*t125[1] / *t125[0], 1.0, 0.12);
  EXPECT_NEAR(*t250[1] / *t250[0], 1.0, 0.12);
}

// Above its Schroeder frequency a box decays as the statistical theory says. A 6 x 4 x 3 m
// box (72 m^3) with absorption 0.2 on every wall: Eyring's T60 is 0.48 s, the Schroeder
// frequency 2000 sqrt(T / V) = 163 Hz, so the 250 Hz octave lies above it; the wave
// solver's walls take that random-incidence absorption (Paris's average of their real
// admittance), and its T20 there must be Eyring's within 10 %.
TEST(WaveLowBand, ABoxAboveItsSchroederFrequencyDecaysAsEyringSays) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({6.0, 4.0, 3.0}), room_reverb::test::uniformLibrary(0.2, 0.5));
  WaveLowBandOptions options;
  options.crossover_hz = 500.0;
  options.threads = 2;
  const WaveLowBand wave = simulateWaveLowBand(scene, kSource, kListener, 343.0, 0.8, options);
  const double eyring = eyringReverberationTimeS(72.0, 108.0, 0.2, 0.0);
  ASSERT_NEAR(2000.0 * std::sqrt(eyring / 72.0), 163.0, 1.0);
  const MetricsReport metrics = computeRoomAcousticParameters(wave.response.channels[0], 48000.0);
  for (std::size_t band : {2u, 3u}) {  // 250, 500 Hz
    ASSERT_TRUE(metrics.bands[band].t20_s) << metrics.bands[band].reason;
    std::cout << "[ measured ] " << metrics.bands[band].nominal_hz << " Hz: T20 " << *metrics.bands[band].t20_s
              << " s against Eyring's " << eyring << " s\n";
  }
  EXPECT_NEAR(*metrics.bands[2].t20_s / eyring, 1.0, 0.1);
  // The crossover's own octave, 7-10 cells per wavelength, decays slower (measured +19 %;
  // +7 % at 15 cells per wavelength): the grid's walls absorb less near its resolution.
  // The join takes the geometric response from its centre up.
  EXPECT_LT(*metrics.bands[3].t20_s / eyring, 1.3);
}

// The join keeps a free-field impulse's energy in every band. A 16 m cube whose walls
// absorb what a real admittance can (0.95), source and listener 6 m apart about its
// centre: the reflections arrive 20 dB down or more, so the response is the direct sound
// (17 ms in, so that the geometric tap's 21 ms of lead-in is not cut). Joined at 250 Hz,
// each octave keeps the energy of the part it takes within 0.5 dB: the wave's below the
// crossover's octave, the geometric one's above, both in it. Measured: the wave part
// carries 0.7 dB more than the geometric one at 63 Hz (the synthesis's lowest band falls
// off below 53 Hz, the wave's does not) and 0.3 dB more at 250 Hz; the join's 250 Hz
// octave lies between them.
TEST(WaveLowBand, TheJoinKeepsAFreeFieldImpulsesEnergyInEveryBand) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({16.0, 16.0, 16.0}), room_reverb::test::uniformLibrary(0.95, 0.0));
  SimulationSettings settings = boxSettings();
  settings.duration_s = 0.08;
  settings.image_source_order = 1;
  settings.rays.ray_count = 200;
  const Eigen::Vector3d source(8.0, 5.0, 8.0), listener(8.0, 11.0, 8.0);
  const auto [geometric, joined] = simulateBothLowBands(scene, source, listener, settings);
  ASSERT_TRUE(joined.low_band.used);
  WaveLowBandOptions options = settings.wave;
  options.threads = 2;
  const WaveLowBand wave = simulateWaveLowBand(scene, source, listener, joined.speed_of_sound_m_s, 0.08, options);
  for (std::size_t band = 0; band < 6; ++band) {  // 63 Hz .. 2 kHz
    const double e = bandEnergyOf(joined.impulse_response.channels[0], band);
    const double to_geometric = 10.0 * std::log10(e / bandEnergyOf(geometric.impulse_response.channels[0], band));
    const double to_wave = 10.0 * std::log10(e / bandEnergyOf(wave.response.channels[0], band));
    std::cout << "[ measured ] octave " << band << ": joined - geometric " << to_geometric << " dB, joined - wave " << to_wave
              << " dB\n";
    if (band <= 1) {  // below the crossover's octave
      EXPECT_NEAR(to_wave, 0.0, 0.5) << "octave " << band;
    } else {  // the crossover's octave and above
      EXPECT_NEAR(to_geometric, 0.0, 0.5) << "octave " << band;
    }
    if (band == 2) {
      EXPECT_NEAR(to_wave, 0.0, 0.5) << "octave " << band;
    }
  }
}
