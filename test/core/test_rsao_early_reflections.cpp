// The early part of the RSAO estimator (Remaggi et al. 2.1) on synthetic shoebox B-format
// RIRs whose image sources are known: times of arrival from the group delay, levels,
// directions, spectra, selection and the checks on bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/acoustics/impulse_response_synthesis.h"
#include "room_reverb/rsao/analysis_window.h"
#include "room_reverb/rsao/early_reflections.h"
#include "room_reverb/rsao/matched_arrivals.h"
#include "shoebox.h"
#include "synthetic_rir.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFs = 48000.0;

// ---------------------------------------------------------------------------------------
// Synthetic rooms
// ---------------------------------------------------------------------------------------

MaterialLibrary frequencyDependentMaterials() {
  MaterialLibrary library;
  const auto add = [&](const char* name, const OctaveBandValues& absorption) {
    AcousticMaterial m;
    m.name = name;
    m.absorption = absorption;
    m.scattering.fill(0.05);
    m.source = "test: octave bands 63 Hz..16 kHz";
    library.add(m);
  };
  add("carpet", {0.02, 0.04, 0.08, 0.2, 0.35, 0.5, 0.6, 0.65, 0.65});  // absorbs the highs
  add("plaster", {0.02, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.1});
  add("ceiling_tile", {0.1, 0.2, 0.4, 0.6, 0.7, 0.75, 0.75, 0.7, 0.7});
  add("glass", {0.3, 0.3, 0.2, 0.1, 0.07, 0.05, 0.03, 0.03, 0.03});     // absorbs the lows
  add("wood", {0.2, 0.25, 0.15, 0.1, 0.1, 0.08, 0.08, 0.08, 0.08});
  return library;
}

struct RoomCase {
  Eigen::Vector3d size, source, receiver;
  // Faces in the order of shoeboxMesh: floor, ceiling, y = 0, y = max, x = 0, x = max.
  std::array<const char*, 6> faces;
};

const std::vector<RoomCase>& roomCases() {
  static const std::vector<RoomCase> cases = {
      {{9.6, 7.3, 3.4}, {2.1, 2.4, 1.5}, {3.9, 3.5, 1.3}, {"carpet", "ceiling_tile", "plaster", "glass", "wood", "plaster"}},
      {{9.6, 7.3, 3.4}, {6.8, 5.1, 1.6}, {5.3, 3.7, 1.2}, {"carpet", "ceiling_tile", "plaster", "glass", "wood", "plaster"}},
      {{12.5, 8.2, 4.6}, {3.3, 5.1, 1.7}, {5.2, 3.9, 1.4}, {"wood", "plaster", "ceiling_tile", "plaster", "glass", "ceiling_tile"}},
      {{12.5, 8.2, 4.6}, {9.1, 2.3, 1.2}, {7.0, 4.6, 1.6}, {"wood", "plaster", "ceiling_tile", "plaster", "glass", "ceiling_tile"}},
      {{6.1, 4.7, 2.9}, {1.4, 3.3, 1.2}, {2.9, 2.2, 1.25}, {"carpet", "ceiling_tile", "plaster", "plaster", "glass", "wood"}},
      {{6.1, 4.7, 2.9}, {4.6, 1.1, 1.5}, {3.2, 2.5, 1.1}, {"carpet", "ceiling_tile", "plaster", "plaster", "glass", "wood"}},
  };
  return cases;
}

TriangleMesh roomMesh(const RoomCase& room) {
  TriangleMesh mesh = room_reverb::test::shoeboxMesh(room.size, room.faces[0]);
  for (std::size_t face = 0; face < 6; ++face) {
    const int material = mesh.materialIndex(room.faces[face]);
    mesh.triangle_material[2 * face] = material;
    mesh.triangle_material[2 * face + 1] = material;
  }
  return mesh;
}

// Energy of the W tap the synthesis renders for unit pressure gain in one octave band
// (and zero in the others). A path's W energy is sum_b g_b^2 bandTapEnergy[b], since the
// tap's power spectrum is sum_b g_b^2 |H_b|^2.
const std::array<double, kOctaveBandCount>& bandTapEnergy() {
  static const auto energies = [] {
    std::array<double, kOctaveBandCount> e{};
    for (int b = 0; b < kOctaveBandCount; ++b) {
      SpecularPath path;
      path.delay_s = 0.05;
      path.pressure_gain.fill(0.0);
      path.pressure_gain[static_cast<std::size_t>(b)] = 1.0;
      SynthesisOptions options;
      options.duration_s = 0.1;
      options.ambisonic_order = 0;
      e[static_cast<std::size_t>(b)] = room_reverb::test::energy(synthesizeImpulseResponse({path}, nullptr, options).channels[0]);
    }
    return e;
  }();
  return energies;
}

struct TrueArrival {
  double time_s;
  double level;  // sqrt of the W tap energy
  Eigen::Vector3d direction;
};

struct SyntheticRir {
  AudioBuffer ambix;
  std::vector<TrueArrival> truth;  // by time; [0] is the direct sound
};

// Image sources to order 8 (the RIR holds exactly these paths, so the truth is complete),
// rendered as first-order AmbiX, plus white noise in every channel 60 dB below W's peak.
SyntheticRir makeRir(const RoomCase& room, std::uint32_t seed, double duration_s = 0.25) {
  const AcousticScene scene(roomMesh(room), frequencyDependentMaterials());
  const PropagationModel model = PropagationModel::from(AirConditions{}, {});
  ImageSourceOptions image_options;
  image_options.max_order = 8;
  const auto paths = computeImageSources(scene, room.source, room.receiver, model, image_options);
  SynthesisOptions synthesis;
  synthesis.duration_s = duration_s;
  synthesis.ambisonic_order = 1;
  SyntheticRir rir;
  rir.ambix = synthesizeImpulseResponse(paths, nullptr, synthesis);
  float peak = 0.0f;
  for (float v : rir.ambix.channels[0]) peak = std::max(peak, std::abs(v));
  for (std::size_t c = 0; c < 4; ++c) {
    const auto noise = room_reverb::test::whiteNoise(rir.ambix.frameCount(), seed + static_cast<std::uint32_t>(c));
    for (std::size_t n = 0; n < noise.size(); ++n) rir.ambix.channels[c][n] += 1e-3f * peak * noise[n];
  }
  for (const auto& p : paths) {
    double e = 0.0;
    for (std::size_t b = 0; b < kOctaveBandCount; ++b) e += p.pressure_gain[b] * p.pressure_gain[b] * bandTapEnergy()[b];
    rir.truth.push_back({p.delay_s, std::sqrt(e), p.arrival_direction});
  }
  std::sort(rir.truth.begin(), rir.truth.end(), [](const TrueArrival& a, const TrueArrival& b) { return a.time_s < b.time_s; });
  return rir;
}

const std::vector<SyntheticRir>& syntheticRirs() {
  static const std::vector<SyntheticRir> rirs = [] {
    std::vector<SyntheticRir> out;
    for (std::size_t i = 0; i < roomCases().size(); ++i) out.push_back(makeRir(roomCases()[i], 100 + 10 * static_cast<std::uint32_t>(i)));
    return out;
  }();
  return rirs;
}

Eigen::Vector3d unitFromAngles(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

double db(double ratio) { return 20.0 * std::log10(ratio); }

// The estimate nearest in time within `tolerance_s`, or null.
const EarlyReflection* nearestEstimate(const std::vector<EarlyReflection>& estimates, double time_s, double tolerance_s) {
  const EarlyReflection* best = nullptr;
  for (const auto& e : estimates) {
    const double error = std::abs(e.time_of_arrival_s - time_s);
    if (error < tolerance_s && (!best || error < std::abs(best->time_of_arrival_s - time_s))) best = &e;
  }
  return best;
}

// A discrete unit impulse at a sample in an otherwise silent 4-channel buffer, from +x.
AudioBuffer impulseBuffer(std::size_t length, std::size_t at) {
  AudioBuffer b = makeSilentBuffer(4, length, kFs);
  b.channels[0][at] = 1.0f;
  b.channels[3][at] = 1.0f;
  return b;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Group delay
// ---------------------------------------------------------------------------------------

TEST(GroupDelayOnsets, AnImpulseMakesALineOfSlopeMinusOneThroughItsSample) {
  std::vector<float> x(400, 0.0f);
  x[200] = 0.7f;
  const std::size_t window = groupDelayWindowLength(0.001, kFs);
  EXPECT_EQ(window, 49u);
  const auto gd = energyWeightedGroupDelay(x, kFs, 180, 221, window);
  for (std::size_t i = 0; i < gd.delay_samples.size(); ++i) {
    EXPECT_NEAR(gd.delay_samples[i], 200.0 - static_cast<double>(180 + i), 1e-12);
  }
  const auto crossings = negativeGoingZeroCrossings(gd);
  ASSERT_EQ(crossings.size(), 1u);
  EXPECT_NEAR(crossings[0].time_s * kFs, 200.0, 1e-9);
}

TEST(GroupDelayOnsets, BandLimitedTapsAreTimedToAFractionOfASample) {
  // The engine's band-limited, fractionally delayed taps (one path each, flat and low-passed).
  // The energy centroid of a sampled band-limited pulse is its delay only to a few
  // hundredths of a sample (the sampled x^2 is not symmetric about a fractional centre),
  // far inside the 0.1 ms (4.8 samples) the estimator must meet.
  for (double delay_samples : {1000.0, 1000.25, 1000.5, 1000.8}) {
    for (bool low_passed : {false, true}) {
      SpecularPath path;
      path.delay_s = delay_samples / kFs;
      for (std::size_t b = 0; b < kOctaveBandCount; ++b) path.pressure_gain[b] = low_passed ? std::pow(0.5, b) : 1.0;
      SynthesisOptions options;
      options.duration_s = 0.05;
      options.ambisonic_order = 0;
      const auto w = synthesizeImpulseResponse({path}, nullptr, options).channels[0];
      const auto gd = energyWeightedGroupDelay(w, kFs, 950, 1050, groupDelayWindowLength(0.001, kFs));
      const auto crossings = negativeGoingZeroCrossings(gd);
      const ArrivalCandidate* strongest = nullptr;
      for (const auto& c : crossings) if (!strongest || c.local_energy > strongest->local_energy) strongest = &c;
      ASSERT_NE(strongest, nullptr);
      EXPECT_NEAR(strongest->time_s * kFs, delay_samples, 0.1) << (low_passed ? "low-passed" : "flat");
    }
  }
}

TEST(GroupDelayOnsets, PruningKeepsStrongPeaksAndMergesCloseCandidates) {
  // A flat local energy of 1 everywhere (so every candidate carries a peak), and candidates
  // with the slope -1 of a clean arrival: 10 ms (energy 1.0), 10.3 ms (0.5: within 0.5 ms
  // of a stronger one), 12 ms (1e-5: below -40 dB), 14 ms (0.2) and 14.4 ms (0.9: the
  // stronger of a close pair).
  GroupDelayFunction gd;
  gd.sample_rate_hz = kFs;
  gd.local_energy.assign(1000, 1.0);
  gd.delay_samples.assign(1000, 0.0);
  const std::vector<ArrivalCandidate> candidates = {
      {0.010, 1.0, -1.0}, {0.0103, 0.5, -1.0}, {0.012, 1e-5, -1.0}, {0.014, 0.2, -1.0}, {0.0144, 0.9, -1.0}};
  const auto kept = pruneCandidates(candidates, gd, 1.0, GroupDelayOnsetOptions{});
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_DOUBLE_EQ(kept[0].time_s, 0.010);
  EXPECT_DOUBLE_EQ(kept[1].time_s, 0.0144);
  // A slope far from -1 (the arrival carries little of its window's energy) is no arrival.
  EXPECT_TRUE(pruneCandidates({{0.010, 1.0, -0.3}}, gd, 1.0, GroupDelayOnsetOptions{}).empty());
  EXPECT_EQ(pruneCandidates({{0.010, 1.0, -0.6}}, gd, 1.0, GroupDelayOnsetOptions{}).size(), 1u);
  // A candidate 0.45 ms beside a local energy peak 20 dB above it carries no peak of its own.
  gd.local_energy[static_cast<std::size_t>(0.01045 * kFs)] = 100.0;
  EXPECT_TRUE(pruneCandidates({{0.010, 1.0, -1.0}}, gd, 1.0, GroupDelayOnsetOptions{}).empty());
}

// ---------------------------------------------------------------------------------------
// The acceptance criteria on synthetic rooms
// ---------------------------------------------------------------------------------------

// The truth to be found: reflections within 20 dB of the direct sound and in the first
// 50 ms after it. Only resolvable ones count: arrivals closer than 1 ms fall inside one
// 2 ms analysis window and cannot be told apart (their time and direction blend), so a
// truth reflection is required only when no other arrival of comparable level (within
// 6 dB of it, or stronger) lies within 1 ms of it. Matching: the nearest estimate within
// 0.5 ms; found means matched with time error < 0.1 ms and direction error < 5 degrees.
// A reported reflection is spurious when no true arrival lies within 0.5 ms of it whose
// level is no more than 10 dB below the reported one (matching a far weaker arrival in a
// dense stretch does not count).
TEST(EarlyReflections, FindsTheResolvableImageSourcesOfShoeboxRooms) {
  EarlyReflectionOptions options;
  options.selection = ReflectionSelection::kAboveLevelThreshold;
  options.level_threshold_db = -25.0;  // 5 dB below the 20 dB of the criterion, for level estimation error
  options.max_reflections = 1000;
  int required = 0, found = 0, reported = 0, spurious = 0;
  double toa_sum_ms = 0.0, toa_max_ms = 0.0, doa_max_deg = 0.0;
  for (std::size_t i = 0; i < syntheticRirs().size(); ++i) {
    const auto& rir = syntheticRirs()[i];
    const auto estimates = estimateEarlyReflections(rir.ambix, options);
    const TrueArrival& direct = rir.truth.front();
    for (std::size_t k = 0; k < rir.truth.size(); ++k) {
      const auto& t = rir.truth[k];
      if (t.time_s - direct.time_s > 0.05 || db(t.level / direct.level) < -20.0) continue;
      bool resolvable = true;
      for (std::size_t j = 0; j < rir.truth.size(); ++j) {
        if (j != k && std::abs(rir.truth[j].time_s - t.time_s) < 0.001 && db(rir.truth[j].level / t.level) > -6.0) resolvable = false;
      }
      if (!resolvable) continue;
      ++required;
      const EarlyReflection* e = nearestEstimate(estimates, t.time_s, 0.0005);
      if (!e) {
        ADD_FAILURE() << "room " << i << ": missed the arrival at " << 1e3 * (t.time_s - direct.time_s) << " ms, "
                      << db(t.level / direct.level) << " dB";
        continue;
      }
      const double toa_ms = 1e3 * std::abs(e->time_of_arrival_s - t.time_s);
      const double doa_deg = angleDeg(unitFromAngles(e->azimuth_rad, e->elevation_rad), t.direction);
      if (toa_ms < 0.1 && doa_deg < 5.0) {
        ++found;
        toa_sum_ms += toa_ms;
        toa_max_ms = std::max(toa_max_ms, toa_ms);
        doa_max_deg = std::max(doa_max_deg, doa_deg);
      }
    }
    for (const auto& e : estimates) {
      ++reported;
      const bool real = std::any_of(rir.truth.begin(), rir.truth.end(), [&](const TrueArrival& t) {
        return std::abs(t.time_s - e.time_of_arrival_s) < 0.0005 && db(t.level / direct.level) > db(e.level / estimates[0].level) - 10.0;
      });
      if (!real) ++spurious;
    }
  }
  std::printf("[ stats    ] %d of %d resolvable reflections found; time error mean %.4f ms, max %.4f ms; "
              "direction error max %.2f deg; %d of %d reported spurious\n",
              found, required, toa_sum_ms / std::max(found, 1), toa_max_ms, doa_max_deg, spurious, reported);
  ASSERT_GE(required, 20);  // enough truth for the rates to mean something
  EXPECT_GE(found, 0.9 * required);
  EXPECT_LE(spurious, 0.1 * reported);
}

TEST(EarlyReflections, DirectSoundIsFirstWithItsTimeLevelDirectionAndDistance) {
  const auto& rir = syntheticRirs()[0];
  const auto estimates = estimateEarlyReflections(rir.ambix);
  ASSERT_FALSE(estimates.empty());
  const auto& d = estimates.front();
  const auto& truth = rir.truth.front();
  EXPECT_NEAR(d.time_of_arrival_s, truth.time_s, 0.1 / kFs);
  EXPECT_LT(angleDeg(unitFromAngles(d.azimuth_rad, d.elevation_rad), truth.direction), 0.5);
  // A_0 = sqrt(E_0): the window (1 at its centre) holds the whole of the short direct tap.
  EXPECT_NEAR(d.level / truth.level, 1.0, 0.03);
  EXPECT_NEAR(d.distance_m, 343.0 * d.time_of_arrival_s, 1e-9);
  const double true_distance = (roomCases()[0].source - roomCases()[0].receiver).norm();
  EXPECT_NEAR(d.distance_m, true_distance, 0.01);  // the engine's c is 343.2
}

TEST(EarlyReflections, ReflectionsAreOrderedAndCarryTheirSpectralModel) {
  const auto& rir = syntheticRirs()[2];
  EarlyReflectionOptions options;
  options.max_reflections = 20;
  const auto estimates = estimateEarlyReflections(rir.ambix, options);
  ASSERT_EQ(estimates.size(), 21u);  // the direct sound and max_reflections
  for (std::size_t i = 1; i < estimates.size(); ++i) {
    EXPECT_GT(estimates[i].time_of_arrival_s, estimates[i - 1].time_of_arrival_s);
    EXPECT_LE(estimates[i].time_of_arrival_s, estimates[0].time_of_arrival_s + 0.08 + 1e-9);
  }
  // Gain matching: the SOS impulse response has the energy of W under the analysis window
  // (the paper's E_k), of the arrival alone for a reflection (W less the pursuit's other
  // arrivals) and of the RIR for the direct sound; matching pursuit's level is the
  // arrival's own amplitude, which the renderer scales the tap to.
  const MatchedPursuit pursuit = matchedPursuit(rir.ambix, estimates[0].time_of_arrival_s,
                                                estimates[0].time_of_arrival_s + options.default_early_duration_s,
                                                options.matched);
  const auto windowEnergy = [&](double time_s, const MatchedArrival* alone) {
    const SampleWindow window = hammingWindowAt(time_s * kFs, 0.002 * kFs, rir.ambix.frameCount());
    double energy = 0.0;
    for (std::size_t i = 0; i < window.weights.size(); ++i) {
      const std::size_t n = window.first + i;
      double w = rir.ambix.channels[0][n];
      if (alone && n >= pursuit.residual_first && n < pursuit.residual_first + pursuit.w_residual.size()) {
        w = pursuit.w_residual[n - pursuit.residual_first];
        if (n >= alone->w_first && n < alone->w_first + alone->w_model.size()) w += alone->w_model[n - alone->w_first];
      }
      energy += std::pow(window.weights[i] * w, 2);
    }
    return energy;
  };
  for (std::size_t k = 0; k < estimates.size(); ++k) {
    const EarlyReflection& r = estimates[k];
    ASSERT_EQ(r.lpc.size(), 10u);
    EXPECT_EQ(r.lpc[0], 1.0);
    EXPECT_EQ(r.sos.size(), 5u);
    std::vector<double> x(20000, 0.0);
    x[0] = 1.0;
    double energy = 0.0;
    for (double v : filterSections(r.sos, x)) energy += v * v;
    const MatchedArrival* alone = nullptr;
    for (const MatchedArrival& m : pursuit.arrivals) {
      if (k > 0 && m.time_s == r.time_of_arrival_s) alone = &m;
    }
    ASSERT_TRUE(k == 0 || alone) << k;
    EXPECT_NEAR(energy / windowEnergy(r.time_of_arrival_s, alone), 1.0, 1e-3) << k;
  }
}

TEST(EarlyReflections, LpcFollowsTheReflectionSpectrum) {
  // One reflection shaped by a wall that absorbs the highs: its order-9 LPC spectrum must
  // fall from 1 kHz to 8 kHz as the rendered tap does, and the direct sound's stay flat.
  SpecularPath direct, reflection;
  direct.delay_s = 0.005;
  direct.pressure_gain.fill(1.0);
  reflection.delay_s = 0.012;
  reflection.arrival_direction = Eigen::Vector3d(0, 1, 0);
  const OctaveBandValues gains{1.0, 1.0, 1.0, 0.9, 0.7, 0.5, 0.3, 0.15, 0.08};
  reflection.pressure_gain = gains;
  SynthesisOptions options;
  options.duration_s = 0.05;
  const AudioBuffer ir = synthesizeImpulseResponse({direct, reflection}, nullptr, options);
  const auto estimates = estimateEarlyReflections(ir);
  ASSERT_EQ(estimates.size(), 2u);
  const auto spectrumDb = [](const EarlyReflection& r, double f) {
    std::complex<double> a = 0.0;
    for (std::size_t i = 0; i < r.lpc.size(); ++i) a += r.lpc[i] * std::polar(1.0, -2.0 * kPi * f / kFs * static_cast<double>(i));
    return 20.0 * std::log10(r.lpc_gain / std::abs(a));
  };
  // Band centres 1, 2, 4, 8 kHz: indices 4..7.
  for (std::size_t b = 5; b <= 7; ++b) {
    const double f = 1000.0 * std::pow(2.0, static_cast<double>(b) - 4.0);
    const double expected = db(gains[b] / gains[4]);
    EXPECT_NEAR(spectrumDb(estimates[1], f) - spectrumDb(estimates[1], 1000.0), expected, 3.0) << f << " Hz";
    EXPECT_NEAR(spectrumDb(estimates[0], f) - spectrumDb(estimates[0], 1000.0), 0.0, 1.5) << f << " Hz";
  }
  EXPECT_NEAR(estimates[1].azimuth_rad, kPi / 2, 0.01);
}

TEST(EarlyReflections, GridSearchAgreesWithTheClosedFormWithinTheStep) {
  const auto& rir = syntheticRirs()[4];
  EarlyReflectionOptions options;
  const auto closed = estimateEarlyReflections(rir.ambix, options);
  options.direction_method = DirectionMethod::kGridSearch;
  options.grid_step_rad = kPi / 180.0;
  const auto grid = estimateEarlyReflections(rir.ambix, options);
  ASSERT_EQ(closed.size(), grid.size());
  for (std::size_t i = 0; i < closed.size(); ++i) {
    EXPECT_EQ(closed[i].time_of_arrival_s, grid[i].time_of_arrival_s);
    EXPECT_LT(angleDeg(unitFromAngles(closed[i].azimuth_rad, closed[i].elevation_rad),
                       unitFromAngles(grid[i].azimuth_rad, grid[i].elevation_rad)),
              1.0)
        << "reflection " << i;
  }
}

TEST(EarlyReflections, SelectionByStrengthOrByLevelAndTheMixingTime) {
  const auto& rir = syntheticRirs()[1];
  EarlyReflectionOptions all;
  all.selection = ReflectionSelection::kAboveLevelThreshold;
  all.level_threshold_db = -60.0;
  all.max_reflections = 100000;
  const auto everything = estimateEarlyReflections(rir.ambix, all);
  ASSERT_GT(everything.size(), 30u);

  EarlyReflectionOptions strongest;
  strongest.max_reflections = 12;
  const auto top = estimateEarlyReflections(rir.ambix, strongest);
  ASSERT_EQ(top.size(), 13u);
  std::vector<double> levels;
  for (std::size_t i = 1; i < everything.size(); ++i) levels.push_back(everything[i].level);
  std::sort(levels.rbegin(), levels.rend());
  for (std::size_t i = 1; i < top.size(); ++i) EXPECT_GE(top[i].level, levels[11]);

  EarlyReflectionOptions above = all;
  above.level_threshold_db = -15.0;
  const auto loud = estimateEarlyReflections(rir.ambix, above);
  std::size_t expected = 0;
  for (std::size_t i = 1; i < everything.size(); ++i) expected += db(everything[i].level / everything[0].level) >= -15.0;
  EXPECT_EQ(loud.size(), expected + 1);
  for (std::size_t i = 1; i < loud.size(); ++i) EXPECT_GE(db(loud[i].level / loud[0].level), -15.0);

  EarlyReflectionOptions early = all;
  early.mixing_time_s = everything[0].time_of_arrival_s + 0.02;
  const auto until_mixing = estimateEarlyReflections(rir.ambix, early);
  ASSERT_GT(until_mixing.size(), 3u);
  EXPECT_LE(until_mixing.back().time_of_arrival_s, *early.mixing_time_s);
  EXPECT_LT(until_mixing.size(), everything.size());
}

// The early part reads only the early part: a 1 s response and its first 150 ms give the
// same reflections (the late tail sets neither the noise floor nor the candidates).
TEST(EarlyReflections, TheLateTailDoesNotMoveTheEarlyReflections) {
  const SyntheticRir rir = makeRir(roomCases()[0], 7, 1.0);
  AudioBuffer head = rir.ambix;
  for (auto& channel : head.channels) channel.resize(static_cast<std::size_t>(0.15 * kFs));
  for (const OnsetMethod method : {OnsetMethod::kMatchedPursuit, OnsetMethod::kGroupDelay}) {
    EarlyReflectionOptions options;
    options.onset_method = method;
    const auto whole = estimateEarlyReflections(rir.ambix, options);
    const auto early = estimateEarlyReflections(head, options);
    ASSERT_GT(whole.size(), 10u);
    ASSERT_EQ(whole.size(), early.size());
    for (std::size_t k = 0; k < whole.size(); ++k) {
      EXPECT_NEAR(whole[k].time_of_arrival_s, early[k].time_of_arrival_s, 1e-12) << k;
      EXPECT_NEAR(whole[k].level, early[k].level, 1e-9 * whole[0].level) << k;
      EXPECT_NEAR(whole[k].azimuth_rad, early[k].azimuth_rad, 1e-9) << k;
    }
  }
}

// ---------------------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------------------

TEST(EarlyReflections, BadInputIsAClearError) {
  AudioBuffer three = impulseBuffer(4800, 100);
  three.channels.pop_back();
  expectInputError([&] { estimateEarlyReflections(three); }, {"at least 4 channels", "got 3"});

  expectInputError([] { estimateEarlyReflections(makeSilentBuffer(4, 4800, kFs)); }, {"W channel", "silent"});

  AudioBuffer nan = impulseBuffer(4800, 100);
  nan.channels[2][300] = std::nanf("");
  expectInputError([&] { estimateEarlyReflections(nan); }, {"channel 2", "NaN"});

  expectInputError([] { estimateEarlyReflections(impulseBuffer(200, 10)); }, {"too short", "200 samples", "at least 10 ms"});

  AudioBuffer slow = impulseBuffer(4800, 100);
  slow.sample_rate_hz = 44100.0;
  expectInputError([&] { estimateEarlyReflections(slow); }, {"44100 Hz", "resample it to 48000 Hz"});

  EarlyReflectionOptions bad;
  bad.analysis_window_s = 0.0;
  expectInputError([&] { estimateEarlyReflections(impulseBuffer(4800, 100), bad); }, {"analysis_window_s"});
  bad = {};
  bad.onsets.window_s = -1.0;
  expectInputError([&] { estimateEarlyReflections(impulseBuffer(4800, 100), bad); }, {"window_s"});
  bad = {};
  bad.mixing_time_s = std::nan("");
  expectInputError([&] { estimateEarlyReflections(impulseBuffer(4800, 100), bad); }, {"mixing_time_s"});
}

TEST(EarlyReflections, TheDirectSoundIsTheFirstStrongArrivalNotTheLoudest) {
  // A direct sound 10.5 dB down (a loudspeaker facing away) from +y, and 45 samples
  // (0.94 ms) later a louder reflection from +x: both near the ISO onset, the earlier wins.
  // (They share most of one 2 ms analysis window, so each direction leans a little
  // towards the other.)
  AudioBuffer b = makeSilentBuffer(4, 4800, kFs);
  b.channels[0][1000] = b.channels[1][1000] = 0.3f;
  b.channels[0][1045] = b.channels[3][1045] = 1.0f;
  const auto estimates = estimateEarlyReflections(b);
  ASSERT_EQ(estimates.size(), 2u);
  EXPECT_NEAR(estimates[0].time_of_arrival_s * kFs, 1000.0, 1e-9);
  EXPECT_NEAR(estimates[0].azimuth_rad, kPi / 2, 0.15);
  EXPECT_NEAR(estimates[1].time_of_arrival_s * kFs, 1045.0, 1e-9);
  EXPECT_NEAR(estimates[1].azimuth_rad, 0.0, 0.01);
}

TEST(EarlyReflections, LevelIsTheHammingWindowedEnergyOfW) {
  // Unit impulse at 1234 and 0.4 at 1270 (0.75 ms later, outside the 1 ms group-delay
  // window, inside the 2 ms analysis window): A_k = sqrt(sum (w W)^2) with the Hamming
  // w(t) = 0.54 + 0.46 cos(2 pi t / D), D = 96 samples, w(36) = 0.54 + 0.46 cos(3 pi / 4).
  AudioBuffer b = makeSilentBuffer(4, 4800, kFs);
  b.channels[0][1234] = b.channels[3][1234] = 1.0f;
  b.channels[0][1270] = b.channels[1][1270] = 0.4f;
  EarlyReflectionOptions paper;  // the paper's level; matching pursuit takes each arrival's own amplitude
  paper.onset_method = OnsetMethod::kGroupDelay;
  const auto estimates = estimateEarlyReflections(b, paper);
  ASSERT_EQ(estimates.size(), 2u);
  const double w36 = 0.54 + 0.46 * std::cos(0.75 * kPi);
  EXPECT_NEAR(estimates[0].level, std::sqrt(1.0 + 0.16 * w36 * w36), 1e-6);
  EXPECT_NEAR(estimates[1].time_of_arrival_s * kFs, 1270.0, 1e-9);
  EXPECT_NEAR(estimates[1].level, std::sqrt(0.16 + w36 * w36), 1e-6);
}

TEST(EarlyReflections, TheDirectSoundsLevelLeavesOutAReflectionInsideItsWindow) {
  // The same pair as above with the pursuit (the default): the reflection 0.75 ms after the
  // direct sound is its own arrival, so neither level holds the other. The window level of
  // the direct sound reads sqrt(1 + r^2 w36^2): 1.004 for r = 0.4, 1.023 for a reflection
  // as loud as the direct sound, more the closer it comes (w(t) rises to 1 at the centre).
  for (const float reflection : {0.4f, 1.0f}) {
    AudioBuffer b = makeSilentBuffer(4, 4800, kFs);
    b.channels[0][1234] = b.channels[3][1234] = 1.0f;
    b.channels[0][1270] = b.channels[1][1270] = reflection;
    const auto estimates = estimateEarlyReflections(b);
    ASSERT_EQ(estimates.size(), 2u) << reflection;
    EXPECT_NEAR(estimates[0].level, 1.0, 1e-3) << reflection;
    EXPECT_NEAR(estimates[1].level, reflection, 1e-3) << reflection;
  }
}

TEST(MatchedPursuit, ItsArrivalsAndItsResidualAddUpToW) {
  // What the pursuit took out and what it left are the RIR's W again, sample by sample, over
  // the span it searched; each arrival's own part is its amplitude times a unit-energy atom.
  const auto& rir = syntheticRirs()[0];
  const double direct_s = rir.truth.front().time_s;
  const MatchedPursuit pursuit = matchedPursuit(rir.ambix, direct_s, direct_s + 0.03);
  ASSERT_GE(pursuit.arrivals.size(), 5u);
  ASSERT_FALSE(pursuit.w_residual.empty());
  std::vector<double> sum = pursuit.w_residual;
  for (const MatchedArrival& m : pursuit.arrivals) {
    ASSERT_GE(m.w_first, pursuit.residual_first);
    ASSERT_LE(m.w_first + m.w_model.size(), pursuit.residual_first + sum.size());
    double energy = 0.0;
    for (std::size_t i = 0; i < m.w_model.size(); ++i) {
      sum[m.w_first - pursuit.residual_first + i] += m.w_model[i];
      energy += m.w_model[i] * m.w_model[i];
    }
    EXPECT_NEAR(std::sqrt(energy), std::abs(m.amplitude), 0.01 * std::abs(m.amplitude));
  }
  double worst = 0.0;
  for (std::size_t i = 0; i < sum.size(); ++i) {
    worst = std::max(worst, std::abs(sum[i] - rir.ambix.channels[0][pursuit.residual_first + i]));
  }
  EXPECT_LT(worst, 1e-6);
  const std::vector<MatchedArrival> arrivals = matchedPursuitArrivals(rir.ambix, direct_s, direct_s + 0.03);
  ASSERT_EQ(arrivals.size(), pursuit.arrivals.size());
  for (std::size_t k = 0; k < arrivals.size(); ++k) EXPECT_EQ(arrivals[k].time_s, pursuit.arrivals[k].time_s);
}

TEST(MatchedPursuit, BadSeparationsAreRefusedInOneLine) {
  for (const auto& [field, value] : {std::pair{"min_separation_s", -1e-4}, std::pair{"min_separation_s", 0.5},
                                     std::pair{"direct_guard_s", -1e-4}, std::pair{"direct_guard_s", std::nan("")}}) {
    MatchedArrivalOptions options;
    (std::string(field) == "min_separation_s" ? options.min_separation_s : options.direct_guard_s) = value;
    expectInputError([&] { validateMatchedArrivalOptions(options); }, {field, "use 0 to 0.01 s"});
  }
}

TEST(EarlyReflections, ALoneImpulseIsTheDirectSoundOnly) {
  const auto estimates = estimateEarlyReflections(impulseBuffer(4800, 1234));
  ASSERT_EQ(estimates.size(), 1u);
  EXPECT_NEAR(estimates[0].time_of_arrival_s * kFs, 1234.0, 1e-9);
  EXPECT_NEAR(estimates[0].azimuth_rad, 0.0, 1e-9);
  EXPECT_NEAR(estimates[0].level, 1.0, 1e-9);
}
