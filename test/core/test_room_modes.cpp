// The modal low band (acoustics/room_modes.h) against what is known of a rectangular room:
// its mode frequencies and their count (Weyl), the decay of an axial mode (Kuttruff's
// weights), the free field its sum must rebuild before the first reflection, and the
// diffuse-field level the ray tracer gives the same room. And the crossover that joins the
// modal band to a ray-traced response.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numeric>
#include <random>

#include "room_reverb/acoustics/room_modes.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/crossover.h"
#include "room_reverb/common/error.h"
#include "room_reverb/diagnosis/response_extensions.h"
#include "shoebox.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

constexpr double kC = 343.0;

ModalRoom uniformBox(const Eigen::Vector3d& size, double alpha) {
  const AcousticScene scene(shoeboxMesh(size), uniformLibrary(alpha, 0.5));
  return modalRoomFromScene(scene, kC);
}

double energy(const std::vector<float>& x, std::size_t from, std::size_t to) {
  double e = 0.0;
  for (std::size_t n = from; n < std::min(to, x.size()); ++n) e += static_cast<double>(x[n]) * x[n];
  return e;
}

TEST(RoomModes, FrequenciesAndCountFollowTheBoxAndWeylsFormula) {
  const Eigen::Vector3d size(5.0, 4.0, 3.0);
  const ModalRoom room = uniformBox(size, 0.1);
  EXPECT_NEAR(room.volumeM3(), 60.0, 1e-9);
  const std::vector<RoomMode> modes = roomModes(room, 250.0);
  ASSERT_FALSE(modes.empty());
  EXPECT_NEAR(modes.front().frequency_hz, kC / (2.0 * 5.0), 1e-9);  // (1, 0, 0)
  EXPECT_EQ(modes.front().index, (std::array<int, 3>{1, 0, 0}));
  // (1, 1, 1) at c/2 sqrt(1/25 + 1/16 + 1/9).
  const auto oblique = std::find_if(modes.begin(), modes.end(), [](const RoomMode& m) { return m.index == std::array<int, 3>{1, 1, 1}; });
  ASSERT_NE(oblique, modes.end());
  EXPECT_NEAR(oblique->frequency_hz, 0.5 * kC * std::sqrt(1.0 / 25 + 1.0 / 16 + 1.0 / 9), 1e-9);
  // Weyl (with Bolt's surface and edge terms): N(f) = 4 pi V f^3 / 3c^3 + pi S f^2 / 4c^2
  // + L f / 8c, L the total edge length. It counts (0, 0, 0) too.
  const double f = 250.0, V = 60.0, S = 2.0 * (20.0 + 15.0 + 12.0), L = 4.0 * 12.0;
  const double weyl = 4.0 * M_PI * V * f * f * f / (3.0 * kC * kC * kC) + M_PI * S * f * f / (4.0 * kC * kC) + L * f / (8.0 * kC) - 1.0;
  std::cout << "[ measured ] " << modes.size() << " modes to 250 Hz, Weyl " << weyl << "\n";
  EXPECT_NEAR(static_cast<double>(modes.size()), weyl, 0.06 * weyl) << modes.size() << " modes, Weyl " << weyl;
}

TEST(RoomModes, AxialModesDecayMoreSlowlyThanObliqueOnesAsKuttruffsWeightsSay) {
  const ModalRoom room = uniformBox({5.0, 4.0, 3.0}, 0.2);
  const double a = -std::log(0.8), c = kC, V = 60.0;
  const double ax = 2 * 12.0 * a, ay = 2 * 15.0 * a, az = 2 * 20.0 * a;  // per wall pair
  for (const RoomMode& m : roomModes(room, 120.0)) {
    const double expected = c / (8 * V) * ((m.index[0] ? 2 : 1) * ax + (m.index[1] ? 2 : 1) * ay + (m.index[2] ? 2 : 1) * az);
    EXPECT_NEAR(m.energy_decay_per_s, expected, 1e-9 * expected);
    if (m.index[0] && m.index[1] && m.index[2]) {
      EXPECT_NEAR(m.energy_decay_per_s, c * (ax + ay + az) / (4 * V), 1e-9);  // Eyring's rate
    }
  }
  // The damping scale multiplies every rate.
  EXPECT_NEAR(roomModes(room, 120.0, 1.5).front().energy_decay_per_s, 1.5 * roomModes(room, 120.0).front().energy_decay_per_s, 1e-12);
}

// One mode alone, (1, 0, 0): the synthesised response must ring at its frequency and
// decay at its rate, with the amplitude of the Green's function.
TEST(RoomModes, ASingleModeRingsAtItsFrequencyAndDecaysAtItsRate) {
  const Eigen::Vector3d size(8.0, 3.0, 2.5);
  const ModalRoom room = uniformBox(size, 0.3);
  const std::vector<RoomMode> modes = roomModes(room, 25.0);
  ASSERT_EQ(modes.size(), 1u);
  ModalSynthesisOptions options;
  options.frames = 48000;
  options.max_frequency_hz = 25.0;
  const Eigen::Vector3d s(1.0, 1.0, 1.0), r(7.0, 2.0, 1.5);
  const AudioBuffer h = synthesizeRoomModes(room, s, r, options);
  ASSERT_EQ(h.channelCount(), 1u);
  const std::vector<float>& x = h.channels[0];
  // Frequency from the zero crossings in the first 0.5 s (interpolated crossing times).
  int crossings = 0;
  double first = 0.0, last = 0.0;
  for (std::size_t n = 2; n < 24000; ++n) {
    if ((x[n - 1] < 0) == (x[n] < 0)) continue;
    last = (n - 1 + x[n - 1] / (x[n - 1] - x[n])) / 48000.0;
    if (crossings++ == 0) first = last;
  }
  // A damped oscillator rings at sqrt(w^2 - delta^2), a little below the mode's frequency.
  const double wn = 2 * M_PI * modes[0].frequency_hz, dn = 0.5 * modes[0].energy_decay_per_s;
  EXPECT_NEAR((crossings - 1) / (2.0 * (last - first)), std::sqrt(wn * wn - dn * dn) / (2 * M_PI), 0.02);
  // Decay: the energy of successive 0.2 s windows.
  const double e1 = energy(x, 0, 9600), e2 = energy(x, 19200, 28800);
  EXPECT_NEAR(std::log(e1 / e2) / 0.4, modes[0].energy_decay_per_s, 0.03 * modes[0].energy_decay_per_s);
  // Amplitude: 4 pi c^2 dt / (V N) psi(S) psi(R) / w with N = 1/2, by projecting the
  // response on exp(-delta t) sin(w t).
  const double w = 2 * M_PI * modes[0].frequency_hz, delta = 0.5 * modes[0].energy_decay_per_s;
  const double amplitude = 4 * M_PI * kC * kC / 48000.0 / (room.volumeM3() * 0.5) * std::cos(M_PI * 1.0 / 8.0) *
                           std::cos(M_PI * 7.0 / 8.0) / w;
  double xy = 0.0, yy = 0.0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    const double t = n / 48000.0, shape = std::exp(-delta * t) * std::sin(std::sqrt(w * w - delta * delta) * t);
    xy += x[n] * shape;
    yy += shape * shape;
  }
  EXPECT_NEAR(xy / yy, amplitude, 0.01 * std::abs(amplitude));
}

// Before the first reflection arrives, the modes of a large room sum to the free field:
// a low-passed pulse at r / c of amplitude 1 / r (the simulator's scale), arriving from
// the source's direction in the first-order channels.
TEST(RoomModes, TheSumOfManyModesRebuildsTheDirectSoundFromTheSourcesDirection) {
  const Eigen::Vector3d size(24.0, 20.0, 16.0);
  const ModalRoom room = uniformBox(size, 0.3);
  ModalSynthesisOptions options;
  options.frames = 4800;  // 0.1 s
  options.max_frequency_hz = 240.0;
  options.ambisonic_order = 1;
  const Eigen::Vector3d s(13.0, 9.0, 8.0), r(10.0, 11.0, 7.0);  // 3.74 m apart, 7 m or more from every wall
  const AudioBuffer h = synthesizeRoomModes(room, s, r, options);
  ASSERT_EQ(h.channelCount(), 4u);
  const double distance = (s - r).norm(), delay = distance / kC;
  // The truth: an impulse of 1/r at the delay, low-passed by the same crossover the
  // modes are used under (120 Hz, an octave wide, well inside the 240 Hz of modes).
  AudioBuffer truth = makeSilentBuffer(1, options.frames, 48000.0);
  truth.channels[0][static_cast<std::size_t>(std::lround(delay * 48000.0))] = static_cast<float>(1.0 / distance);
  AudioBuffer modes_only = h;
  modes_only.channels.resize(1);
  const AudioBuffer zero = makeSilentBuffer(1, options.frames, 48000.0);
  const AudioBuffer low_truth = joinAtCrossover(truth, zero, 120.0);
  const AudioBuffer low_modes = joinAtCrossover(modes_only, zero, 120.0);
  // The first reflection arrives 2 * 7 m later at the earliest: compare up to then.
  const std::size_t end = static_cast<std::size_t>((delay + 0.02) * 48000.0);
  const double e_truth = energy(low_truth.channels[0], 0, end), e_modes = energy(low_modes.channels[0], 0, end);
  std::cout << "[ measured ] modal / free-field direct energy: " << 10 * std::log10(e_modes / e_truth) << " dB\n";
  EXPECT_NEAR(10 * std::log10(e_modes / e_truth), 0.0, 1.0);
  double error = 0.0;
  for (std::size_t n = 0; n < end; ++n) error += std::pow(low_modes.channels[0][n] - low_truth.channels[0][n], 2);
  std::cout << "[ measured ] waveform error " << 10 * std::log10(error / e_truth) << " dB re the pulse\n";
  EXPECT_LT(error, 0.1 * e_truth) << "the waveform differs from the low-passed pulse";
  // Direction: the intensity W * (X, Y, Z) summed over the pulse, against the arrival
  // direction (from the receiver towards the source).
  AudioBuffer low = joinAtCrossover(h, makeSilentBuffer(4, options.frames, 48000.0), 120.0);
  Eigen::Vector3d intensity = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < end; ++n) {
    intensity += low.channels[0][n] * Eigen::Vector3d(low.channels[3][n], low.channels[1][n], low.channels[2][n]);
  }
  const Eigen::Vector3d arrival = (s - r).normalized();
  std::cout << "[ measured ] direction error " << std::acos(std::min(1.0, intensity.normalized().dot(arrival))) * 180 / M_PI << " deg\n";
  EXPECT_GT(intensity.normalized().dot(arrival), std::cos(10.0 * M_PI / 180.0)) << intensity.transpose();
}

// In the reverberant field, averaged over receivers, the modes carry the energy the ray
// tracer gives the same room in the 125 Hz octave: the two halves of a joined response
// meet at one level.
TEST(RoomModes, TheReverberantLevelMatchesTheRayTracersIn125HzOctave) {
  const Eigen::Vector3d size(6.0, 4.5, 3.0);
  const AcousticScene scene(shoeboxMesh(size), uniformLibrary(0.15, 0.5));
  const ModalRoom room = modalRoomFromScene(scene, speedOfSoundMPerS(20.0));
  SimulationSettings settings;
  settings.duration_s = 0.6;
  settings.ambisonic_order = 0;
  settings.air.enabled = false;
  settings.rays.ray_count = 8000;
  ModalSynthesisOptions options;
  options.frames = static_cast<std::size_t>(0.6 * 48000);
  options.max_frequency_hz = 400.0;
  const BandFilterBank bank({standardBands(BandResolution::kOctave)[1]}, 48000.0);  // 125 Hz
  double rays = 0.0, modal = 0.0;
  const Eigen::Vector3d source(1.3, 1.1, 1.4);
  for (const Eigen::Vector3d& receiver : {Eigen::Vector3d(4.6, 3.1, 1.2), Eigen::Vector3d(3.7, 1.2, 1.7),
                                          Eigen::Vector3d(2.2, 3.5, 1.1), Eigen::Vector3d(5.0, 2.0, 2.1),
                                          Eigen::Vector3d(3.1, 2.6, 0.9), Eigen::Vector3d(4.2, 0.9, 2.4)}) {
    settings.rays.seed += 1;
    const SimulationResult result = simulateRoom(scene, source, receiver, settings);
    const AudioBuffer m = synthesizeRoomModes(room, source, receiver, options);
    // 50-400 ms: past the direct sound and the first reflections.
    rays += energy(bank.split(result.impulse_response.channels[0])[0], 2400, 19200);
    modal += energy(bank.split(m.channels[0])[0], 2400, 19200);
  }
  std::cout << "[ measured ] modal / ray-traced energy, 125 Hz, 50-400 ms: " << 10 * std::log10(modal / rays) << " dB\n";
  EXPECT_NEAR(10 * std::log10(modal / rays), 0.0, 1.5);
}

// The diagnosis's extension (response_extensions.h): the modal band replaces the rays'
// below the crossover and leaves the octaves above it as they were.
TEST(RoomModes, TheModalExtensionChangesOnlyTheBandsBelowItsCrossover) {
  const AcousticScene scene(shoeboxMesh({6.0, 4.5, 3.0}), uniformLibrary(0.15, 0.5));
  SimulationSettings settings;
  settings.duration_s = 0.6;
  settings.ambisonic_order = 1;
  settings.rays.ray_count = 4000;
  MeasurementPair pair;
  pair.source_m = {1.3, 1.1, 1.4};
  pair.receiver_m = {4.6, 3.1, 1.2};
  const SimulationResult result = simulateRoom(scene, pair.source_m, pair.receiver_m, settings);
  ModelExtension extension;
  extension.modes = LowFrequencyModes{1.0, modalCrossoverHz(scene, settings.air)};
  EXPECT_NEAR(extension.modes->crossover_hz, schroederFrequencyHz(0.5 * (eyringReverberationTimes(scene, settings.air)[3] +
                                                                         eyringReverberationTimes(scene, settings.air)[4]),
                                                                  scene.volumeM3()), 1e-9);
  AudioBuffer extended = result.impulse_response;
  const ModalRoom room = modalRoomFor(scene, settings.air);
  applyResponseExtensions(extended, extension, &room, pair, result.paths.front().delay_s, 1);
  ASSERT_EQ(extended.channelCount(), 4u);
  const std::vector<FrequencyBand> octaves = standardBands(BandResolution::kOctave);
  const BandFilterBank bank(octaves, 48000.0);
  for (std::size_t ch = 0; ch < 4; ++ch) {
    const auto before = bank.split(result.impulse_response.channels[ch]), after = bank.split(extended.channels[ch]);
    for (std::size_t b = 0; b < octaves.size(); ++b) {
      const double change_db = 10 * std::log10(energy(after[b], 0, after[b].size()) / energy(before[b], 0, before[b].size()));
      if (octaves[b].lower_hz > extension.modes->crossover_hz * std::sqrt(2.0)) {
        EXPECT_NEAR(change_db, 0.0, 0.01) << "channel " << ch << ", " << octaves[b].nominal_hz << " Hz";
      }
    }
  }
  // The modes need their room.
  EXPECT_THROW(applyResponseExtensions(extended, extension, nullptr, pair, 0.0, 1), InputError);
}

TEST(RoomModes, BadInputGetsAClearError) {
  const ModalRoom room = uniformBox({5.0, 4.0, 3.0}, 0.1);
  ModalSynthesisOptions options;
  options.frames = 100;
  EXPECT_THROW(synthesizeRoomModes(room, {6.0, 1.0, 1.0}, {1.0, 1.0, 1.0}, options), InputError);
  EXPECT_THROW(synthesizeRoomModes(room, {1.0, 1.0, 1.0}, {1.0, NAN, 1.0}, options), InputError);
  options.ambisonic_order = 2;
  EXPECT_THROW(synthesizeRoomModes(room, {1.0, 1.0, 1.0}, {2.0, 1.0, 1.0}, options), InputError);
  options.ambisonic_order = 0;
  options.frames = 0;
  EXPECT_THROW(synthesizeRoomModes(room, {1.0, 1.0, 1.0}, {2.0, 1.0, 1.0}, options), InputError);
  options.frames = 100;
  options.max_frequency_hz = 30000.0;
  EXPECT_THROW(synthesizeRoomModes(room, {1.0, 1.0, 1.0}, {2.0, 1.0, 1.0}, options), InputError);
  EXPECT_THROW(roomModes(room, 100.0, 0.0), InputError);
  EXPECT_THROW(roomModes(room, -1.0), InputError);
  EXPECT_THROW(schroederFrequencyHz(0.0, 100.0), InputError);
  EXPECT_NEAR(schroederFrequencyHz(1.0, 100.0), 200.0, 1e-9);
}

TEST(Crossover, AResponseJoinedWithItselfIsUnchangedAndTheBandsComeFromEachSide) {
  std::vector<float> a(48000), b(48000);
  std::mt19937 rng(3);
  std::normal_distribution<float> noise;
  for (std::size_t n = 0; n < a.size(); ++n) {
    a[n] = noise(rng);
    b[n] = noise(rng);
  }
  AudioBuffer x, y;
  x.channels = {a};
  y.channels = {b};
  const AudioBuffer same = joinAtCrossover(x, x, 200.0);
  double diff = 0.0;
  for (std::size_t n = 0; n < a.size(); ++n) diff = std::max(diff, static_cast<double>(std::abs(same.channels[0][n] - a[n])));
  EXPECT_LT(diff, 1e-4);
  // x below, y above: the 63 Hz octave is x's, the 1 kHz octave is y's.
  const AudioBuffer joined = joinAtCrossover(x, y, 200.0);
  const BandFilterBank bank({standardBands(BandResolution::kOctave)[0], standardBands(BandResolution::kOctave)[4]}, 48000.0);
  const auto j = bank.split(joined.channels[0]), xs = bank.split(a), ys = bank.split(b);
  double e_low = 0, e_low_err = 0, e_high = 0, e_high_err = 0;
  for (std::size_t n = 4800; n + 4800 < a.size(); ++n) {  // away from the ends, where the filters ring out
    e_low += xs[0][n] * xs[0][n];
    e_low_err += std::pow(j[0][n] - xs[0][n], 2);
    e_high += ys[1][n] * ys[1][n];
    e_high_err += std::pow(j[1][n] - ys[1][n], 2);
  }
  EXPECT_LT(e_low_err, 1e-3 * e_low);
  EXPECT_LT(e_high_err, 1e-3 * e_high);
  EXPECT_NEAR(crossoverLowGain(200.0, 200.0), 0.5, 1e-12);
  EXPECT_EQ(crossoverLowGain(100.0, 200.0), 1.0);
  EXPECT_EQ(crossoverLowGain(400.0, 200.0), 0.0);
}

TEST(Crossover, BadInputGetsAClearError) {
  AudioBuffer x = makeSilentBuffer(1, 100, 48000.0), y = makeSilentBuffer(1, 100, 44100.0);
  EXPECT_THROW(joinAtCrossover(x, y, 200.0), InputError);
  EXPECT_THROW(joinAtCrossover(x, x, 0.0), InputError);
  EXPECT_THROW(joinAtCrossover(x, x, 30000.0), InputError);
  EXPECT_THROW(joinAtCrossover(x, x, 200.0, 0.0), InputError);
  // Fewer channels in the low side: the rest stay as they were.
  AudioBuffer four = makeSilentBuffer(4, 100, 48000.0);
  four.channels[3][10] = 1.0f;
  EXPECT_EQ(joinAtCrossover(x, four, 200.0).channels[3][10], 1.0f);
}

}  // namespace
}  // namespace room_reverb::test
