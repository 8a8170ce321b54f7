#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/binaural/diffuse_field.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/binaural/rsao_binaural.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/late_reverb.h"
#include "synthetic_rsao.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

constexpr double kFs = 48000.0;
const std::string kKu100 = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/hrtf/FHK_HRIR_L2354.sofa";

// Loaded once for the whole file (a fifth of a second), its diffuse-field spectrum too.
const HrtfSet& ku100() {
  static const HrtfSet set = HrtfSet::loadSofa(kKu100);
  return set;
}
const DiffuseFieldSpectrum& ku100DiffuseField() {
  static const DiffuseFieldSpectrum spectrum = diffuseFieldSpectrum(ku100());
  return spectrum;
}

EarlyReflection tap(double toa_s, double level, const Eigen::Vector3d& direction) {
  EarlyReflection r;
  r.time_of_arrival_s = toa_s;
  r.level = level;
  r.azimuth_rad = std::atan2(direction.y(), direction.x());
  r.elevation_rad = std::asin(std::clamp(direction.z() / direction.norm(), -1.0, 1.0));
  return r;
}

Eigen::Vector3d fromDegrees(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * M_PI / 180.0, el = elevation_deg * M_PI / 180.0;
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

// Direct sound from ahead at 3 ms, one reflection at `toa_s` from `direction`; no late
// part.
Rsao oneReflection(const Eigen::Vector3d& direction, double toa_s = 0.0123456) {
  Rsao rsao;
  rsao.duration_s = 0.05;
  rsao.reflections.push_back(tap(0.003, 1.0, Eigen::Vector3d::UnitX()));
  rsao.reflections.push_back(tap(toa_s, 0.5, direction));
  return rsao;
}

// A room-like late part (decay and level falling with frequency), onset at 10 ms, mixing
// time at 60 ms, and a direct sound.
const std::vector<double>& kT60 = room_reverb::test::roomLikeT60s();
const std::vector<double>& kLevel = room_reverb::test::roomLikeLevels();

Rsao roomLike(double duration_s) {
  Rsao rsao = room_reverb::test::roomLikeLateRsao(duration_s);
  rsao.reflections.push_back(tap(0.004, 0.3, Eigen::Vector3d::UnitX()));
  return rsao;
}

// Normalised correlation of the two ears' signals from sample `lag` on with the HRIR pair
// `h`: sum over both ears of y . h / sqrt(|y|^2 |h|^2).
double normalisedCorrelation(const AudioBuffer& ears, long lag, const Hrir& h) {
  double cross = 0.0, ear_energy = 0.0, h_energy = 0.0;
  for (std::size_t ear = 0; ear < 2; ++ear) {
    const std::vector<float>& hrir = ear == 0 ? h.left : h.right;
    for (std::size_t i = 0; i < hrir.size(); ++i) {
      const double y = ears.channels[ear][static_cast<std::size_t>(lag) + i];
      cross += y * hrir[i];
      ear_energy += y * y;
      h_energy += static_cast<double>(hrir[i]) * hrir[i];
    }
  }
  return cross / std::sqrt(ear_energy * h_energy);
}

struct BestMatch {
  std::size_t direction = 0;
  long lag = 0;
  double correlation = -2.0;
};

// Over every measured direction of the set and lags within 4 samples of `around`: the HRIR
// pair that matches the ears' signals best.
BestMatch bestMatch(const AudioBuffer& ears, long around) {
  BestMatch best;
  for (std::size_t d = 0; d < ku100().size(); ++d) {
    for (long lag = around - 4; lag <= around + 4; ++lag) {
      const double r = normalisedCorrelation(ears, lag, ku100().hrir(d));
      if (r > best.correlation) best = {d, lag, r};
    }
  }
  return best;
}

double energy(const std::vector<float>& x, std::size_t first, std::size_t last) {
  double e = 0.0;
  for (std::size_t n = first; n < last && n < x.size(); ++n) e += static_cast<double>(x[n]) * x[n];
  return e;
}

}  // namespace

TEST(RsaoBinaural, ReflectionArrivesAtItsDelayFromItsDirection) {
  // On a whole sample the tap is the HRIR pair itself, so of all the set's directions the
  // true one must match best, at the arrival. (Between samples a neighbouring direction
  // whose onsets differ by the fraction can match the integer lags better.)
  const std::size_t truth = ku100().nearest(fromDegrees(60.0, 20.0));
  const long delay = 594;
  const Rsao rsao = oneReflection(ku100().direction(truth), static_cast<double>(delay) / kFs);
  RsaoBinauralOptions options;
  const AudioBuffer brir = renderRsaoBinaural(rsao, ku100(), options);
  ASSERT_EQ(brir.channelCount(), 2u);
  EXPECT_EQ(brir.sample_rate_hz, kFs);
  const BestMatch best = bestMatch(brir, delay);
  std::printf("best direction %zu (truth %zu), lag %ld (delay %ld), correlation %.6f; runner-up direction: ",
              best.direction, truth, best.lag, delay, best.correlation);
  EXPECT_EQ(best.direction, truth);
  EXPECT_LE(std::abs(best.lag - delay), 1);
  double runner_up = -1.0;
  for (std::size_t d = 0; d < ku100().size(); ++d) {
    if (d == truth) continue;
    for (long lag = delay - 4; lag <= delay + 4; ++lag) runner_up = std::max(runner_up, normalisedCorrelation(brir, lag, ku100().hrir(d)));
  }
  std::printf("%.4f\n", runner_up);

  // Turning the head turns the reflection: with the head turned by the reflection's own
  // azimuth and elevation it comes from straight ahead.
  const EarlyReflection& r = rsao.reflections[1];
  options.head_in_rig = (Eigen::AngleAxisd(r.azimuth_rad, Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(-r.elevation_rad, Eigen::Vector3d::UnitY()))
                            .toRotationMatrix();
  const AudioBuffer turned = renderRsaoBinaural(rsao, ku100(), options);
  EXPECT_EQ(bestMatch(turned, delay).direction, ku100().nearest(Eigen::Vector3d::UnitX()));
}

TEST(RsaoBinaural, ReflectionArrivesBetweenSamples) {
  // The peak of the correlation with the true pair, refined by a parabola through its
  // three highest lags, falls on the fractional arrival.
  const std::size_t truth = ku100().nearest(fromDegrees(-135.0, 0.0));
  const double arrival = 0.0123456 * kFs;
  const AudioBuffer brir = renderRsaoBinaural(oneReflection(ku100().direction(truth), arrival / kFs), ku100());
  const auto whole = static_cast<long>(std::floor(arrival));
  long peak = whole;
  for (long lag = whole - 2; lag <= whole + 2; ++lag) {
    if (normalisedCorrelation(brir, lag, ku100().hrir(truth)) > normalisedCorrelation(brir, peak, ku100().hrir(truth))) {
      peak = lag;
    }
  }
  const double before = normalisedCorrelation(brir, peak - 1, ku100().hrir(truth));
  const double at = normalisedCorrelation(brir, peak, ku100().hrir(truth));
  const double after = normalisedCorrelation(brir, peak + 1, ku100().hrir(truth));
  const double refined = static_cast<double>(peak) + 0.5 * (before - after) / (before - 2.0 * at + after);
  std::printf("arrival %.3f samples, correlation peak at %.3f\n", arrival, refined);
  EXPECT_NEAR(refined, arrival, 0.15);
}

TEST(RsaoBinaural, ReflectionFromTheLeftIsLouderInTheLeftEar) {
  const long first = std::lround(0.0123456 * kFs) - 20, last = first + 200;
  for (const double azimuth_deg : {90.0, -90.0}) {
    const AudioBuffer brir = renderRsaoBinaural(oneReflection(fromDegrees(azimuth_deg, 0.0)), ku100());
    const double ild_db = 10.0 * std::log10(energy(brir.channels[0], first, last) / energy(brir.channels[1], first, last));
    std::printf("reflection from %+.0f deg: ILD (left re right) %+.1f dB\n", azimuth_deg, ild_db);
    EXPECT_GT(azimuth_deg > 0.0 ? ild_db : -ild_db, 6.0);
  }
}

TEST(RsaoBinaural, LateReverbHasTheDiffuseFieldCoherenceLevelAndDecayAtEachEar) {
  const Rsao rsao = roomLike(2.0);
  RsaoBinauralOptions options;
  options.resynthesis.include_early = false;
  const AudioBuffer brir = renderRsaoBinaural(rsao, ku100(), ku100DiffuseField(), options);

  const std::vector<FrequencyBand> octaves = standardBands(BandResolution::kOctave);
  std::vector<double> centres;
  for (const FrequencyBand& band : octaves) centres.push_back(band.nominal_hz);
  const std::vector<double> target = diffuseFieldCoherence(ku100DiffuseField(), centres);
  const BandFilterBank bank(octaves, kFs);
  const std::vector<std::vector<float>> left = bank.split(brir.channels[0]);
  const std::vector<std::vector<float>> right = bank.split(brir.channels[1]);
  const LateReverb late_left = estimateLateReverb(brir.channels[0], rsao.late.onset_s, rsao.late.mixing_time_s);
  const LateReverb late_right = estimateLateReverb(brir.channels[1], rsao.late.onset_s, rsao.late.mixing_time_s);
  const DiffuseFieldSpectrum& spectrum = ku100DiffuseField();
  for (std::size_t b = 1; b + 1 < octaves.size(); ++b) {  // 125 Hz .. 8 kHz
    double cross = 0.0, ll = 0.0, rr = 0.0;
    for (std::size_t n = 0; n < left[b].size(); ++n) {
      cross += static_cast<double>(left[b][n]) * right[b][n];
      ll += static_cast<double>(left[b][n]) * left[b][n];
      rr += static_cast<double>(right[b][n]) * right[b][n];
    }
    const double coherence = cross / std::sqrt(ll * rr);
    // The ear's expected level: the W level times the root of the diffuse-field power
    // response, here simply averaged over the band's bins.
    double power_left = 0.0, power_right = 0.0;
    int bins = 0;
    for (std::size_t k = 1; k < spectrum.power_left.size(); ++k) {
      const double f = static_cast<double>(k) * spectrum.bin_spacing_hz;
      if (f < octaves[b].lower_hz || f >= octaves[b].upper_hz) continue;
      power_left += spectrum.power_left[k];
      power_right += spectrum.power_right[k];
      ++bins;
    }
    const double level_error_left_db =
        20.0 * std::log10(late_left.bands[b].level / (rsao.late.bands[b].level * std::sqrt(power_left / bins)));
    const double level_error_right_db =
        20.0 * std::log10(late_right.bands[b].level / (rsao.late.bands[b].level * std::sqrt(power_right / bins)));
    const double t60_error_left = late_left.bands[b].t60_s / kT60[b] - 1.0;
    const double t60_error_right = late_right.bands[b].t60_s / kT60[b] - 1.0;
    std::printf("%5.0f Hz: coherence %+.3f (target %+.3f), T60 error L %+.1f %% R %+.1f %%, level error L %+.2f dB R %+.2f dB\n",
                octaves[b].nominal_hz, coherence, target[b], 100.0 * t60_error_left, 100.0 * t60_error_right,
                level_error_left_db, level_error_right_db);
    EXPECT_NEAR(coherence, target[b], 0.1) << octaves[b].nominal_hz << " Hz";
    EXPECT_NEAR(t60_error_left, 0.0, 0.05) << octaves[b].nominal_hz << " Hz";
    EXPECT_NEAR(t60_error_right, 0.0, 0.05) << octaves[b].nominal_hz << " Hz";
    EXPECT_NEAR(level_error_left_db, 0.0, 1.0) << octaves[b].nominal_hz << " Hz";
    EXPECT_NEAR(level_error_right_db, 0.0, 1.0) << octaves[b].nominal_hz << " Hz";
  }
}

TEST(RsaoBinaural, SameSeedSameSamplesOtherSeedOtherNoise) {
  Rsao rsao = roomLike(0.3);
  rsao.reflections.push_back(tap(0.011, 0.1, fromDegrees(-120.0, 10.0)));
  RsaoBinauralOptions options;
  const AudioBuffer a = renderRsaoBinaural(rsao, ku100(), ku100DiffuseField(), options);
  const AudioBuffer b = renderRsaoBinaural(rsao, ku100(), ku100DiffuseField(), options);
  EXPECT_EQ(a.channels, b.channels);
  options.resynthesis.seed = 2;
  const AudioBuffer c = renderRsaoBinaural(rsao, ku100(), ku100DiffuseField(), options);
  EXPECT_NE(a.channels, c.channels);
  // The early part does not depend on the seed: up to the onset of the late part the
  // renders agree.
  const auto onset = static_cast<std::size_t>(rsao.late.onset_s * kFs);
  for (std::size_t ear = 0; ear < 2; ++ear) {
    EXPECT_EQ(std::vector<float>(a.channels[ear].begin(), a.channels[ear].begin() + onset),
              std::vector<float>(c.channels[ear].begin(), c.channels[ear].begin() + onset));
  }
}

TEST(RsaoBinaural, RejectsWhatItCannotRender) {
  Rsao no_direct = roomLike(0.2);
  no_direct.reflections.clear();
  expectInputError([&] { renderRsaoBinaural(no_direct, ku100()); }, {"binaural RSAO", "no direct sound"});

  const HrtfSet at_44k(44100.0, {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()},
                       {Hrir{{1.0f, 0.0f}, {0.5f, 0.0f}}, Hrir{{1.0f, 0.0f}, {0.2f, 0.0f}}});
  expectInputError([&] { renderRsaoBinaural(oneReflection(Eigen::Vector3d::UnitY()), at_44k); },
                   {"44100 Hz", "48000 Hz"});

  Rsao bad = oneReflection(Eigen::Vector3d::UnitY());
  bad.reflections[1].time_of_arrival_s = std::nan("");
  expectInputError([&] { renderRsaoBinaural(bad, ku100()); }, {"binaural RSAO", "reflection 1", "finite"});
  bad = oneReflection(Eigen::Vector3d::UnitY());
  bad.reflections[0].azimuth_rad = INFINITY;
  expectInputError([&] { renderRsaoBinaural(bad, ku100()); }, {"the direct sound", "finite direction"});
  bad = roomLike(0.2);
  bad.late.bands[4].decay_constant_per_s = std::nan("");
  expectInputError([&] { renderRsaoBinaural(bad, ku100()); }, {"1000 Hz", "positive decay constant"});

  RsaoBinauralOptions options;
  options.head_in_rig(0, 0) = std::nan("");
  expectInputError([&] { renderRsaoBinaural(oneReflection(Eigen::Vector3d::UnitY()), ku100(), options); },
                   {"head_in_rig", "proper rotation"});
  options.head_in_rig = -Eigen::Matrix3d::Identity();  // a reflection, not a rotation
  expectInputError([&] { renderRsaoBinaural(oneReflection(Eigen::Vector3d::UnitY()), ku100(), options); },
                   {"head_in_rig"});
  expectInputError([&] { renderRsaoBinaural(roomLike(0.2), ku100(), DiffuseFieldSpectrum{}); },
                   {"diffuse-field spectrum"});
}

// Not a pass/fail check: the time a typical object takes (20 reflections, 1.5 s).
TEST(RsaoBinaural, RenderTimeOfATypicalObject) {
  Rsao rsao = roomLike(1.5);
  for (int k = 1; k <= 20; ++k) {
    EarlyReflection r = tap(0.004 + 0.0025 * k, 0.3 / (1.0 + 0.2 * k), fromDegrees(-180.0 + 17.0 * k, 40.0 - 4.0 * k));
    r.sos = {BiquadSection{0.6, 0.3, 0.0, -0.2, 0.0}};  // a gentle low-pass, as a fitted filter would be
    rsao.reflections.push_back(r);
  }
  rsao.late.onset_s = rsao.reflections[1].time_of_arrival_s;
  const auto start = std::chrono::steady_clock::now();
  const AudioBuffer with_spectrum = renderRsaoBinaural(rsao, ku100(), ku100DiffuseField());
  const auto middle = std::chrono::steady_clock::now();
  const AudioBuffer without = renderRsaoBinaural(rsao, ku100());
  const auto end = std::chrono::steady_clock::now();
  std::printf("render of 20 reflections and a 1.5 s late part: %.0f ms with the diffuse-field spectrum given, %.0f ms "
              "computing it\n",
              1e3 * std::chrono::duration<double>(middle - start).count(),
              1e3 * std::chrono::duration<double>(end - middle).count());
  EXPECT_EQ(with_spectrum.channels, without.channels);
}
