// Each early reflection of the RSAO as an image source (distance along its direction) and
// with a confidence: the directness measure itself on fields whose answer is known, then
// the estimator on the synthetic rooms of reflection_rooms.h, whose image sources are
// exact. The held-out rooms (other seeds, shapes, a reflector panel) are only scored.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "reflection_rooms.h"
#include "reflection_score.h"
#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/quantile.h"
#include "room_reverb/rsao/direction_of_arrival.h"
#include "room_reverb/rsao/early_reflections.h"

using namespace room_reverb::core;
using room_reverb::test::reflectionRoom;
using room_reverb::test::reflectionRoomCount;
using room_reverb::test::ReflectionRoomSet;

namespace {

constexpr double kC = 343.0;  // the rooms' speed of sound, and the estimator's default

// Statistics of `frames` samples of first-order AmbiX (SN3D) made by `sample`.
template <typename Sample>
CardioidSteeringStatistics statisticsOf(std::size_t frames, Sample sample) {
  AudioBuffer ambix = makeSilentBuffer(4, frames, 48000.0);
  for (std::size_t n = 0; n < frames; ++n) {
    const std::array<double, 4> wxyz = sample(n);
    ambix.channels[kAcnW][n] = static_cast<float>(wxyz[0]);
    ambix.channels[kAcnX][n] = static_cast<float>(wxyz[1]);
    ambix.channels[kAcnY][n] = static_cast<float>(wxyz[2]);
    ambix.channels[kAcnZ][n] = static_cast<float>(wxyz[3]);
  }
  SampleWindow window;
  window.first = 0;
  window.weights.assign(frames, 1.0);
  return steeringStatistics(ambix, window);
}

Eigen::Vector3d unitFrom(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

Eigen::Vector3d position(const EarlyReflection& r) {
  const auto p = imageSourcePosition(r);
  return {p[0], p[1], p[2]};
}

double median(std::vector<double> values) { return values.empty() ? 0.0 : quantileLinear(values, 0.5); }

}  // namespace

TEST(ReflectionConfidence, DirectnessIsOneForAPlaneWaveAndFallsWithDiffuseOrSecondArrivals) {
  std::mt19937 random(7);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  const Eigen::Vector3d u = unitFrom(0.7, 0.2), v = unitFrom(0.7 + 1.5707963, 0.0);  // orthogonal
  // One plane wave: X, Y, Z = u W.
  const auto plane = statisticsOf(2000, [&](std::size_t) {
    const double s = gaussian(random);
    return std::array<double, 4>{s, u.x() * s, u.y() * s, u.z() * s};
  });
  EXPECT_NEAR(plane.directness(), 1.0, 1e-6);
  // Two uncorrelated plane waves of equal energy from orthogonal directions: |p| = sqrt(2) E,
  // Eww + tr R = 4 E, so 1/sqrt(2).
  const auto two = statisticsOf(200000, [&](std::size_t) {
    const double a = gaussian(random), b = gaussian(random);
    const Eigen::Vector3d xyz = a * u + b * v;
    return std::array<double, 4>{a + b, xyz.x(), xyz.y(), xyz.z()};
  });
  EXPECT_NEAR(two.directness(), 1.0 / std::sqrt(2.0), 0.01);
  // An isotropic diffuse field in SN3D: X, Y, Z uncorrelated with W, each with a third of
  // its energy.
  const auto diffuse = statisticsOf(200000, [&](std::size_t) {
    return std::array<double, 4>{gaussian(random), gaussian(random) / std::sqrt(3.0), gaussian(random) / std::sqrt(3.0),
                                 gaussian(random) / std::sqrt(3.0)};
  });
  EXPECT_LT(diffuse.directness(), 0.02);
  EXPECT_EQ(statisticsOf(100, [](std::size_t) { return std::array<double, 4>{0, 0, 0, 0}; }).directness(), 0.0);
}

// Scored on the resolvable reflections (reflection_score.h) that the estimator finds,
// with the direct sound's true distance given (the rooms start at the emission, so the
// default, c times the direct sound's time, gives the same). Both onset methods: matching
// pursuit (the default) points every found reflection within a few degrees; the paper's
// onsets point some far off, and there the confidence must tell them apart.
TEST(ReflectionImageSources, PlacedWhereTheRoomsImageSourcesAre) {
  for (const OnsetMethod method : {OnsetMethod::kMatchedPursuit, OnsetMethod::kGroupDelay}) {
    for (const ReflectionRoomSet set : {ReflectionRoomSet::kDevelopment, ReflectionRoomSet::kHeldOut}) {
      const std::string name = std::string(set == ReflectionRoomSet::kDevelopment ? "development" : "held-out") +
                               (method == OnsetMethod::kGroupDelay ? ", paper's onsets" : ", matching pursuit");
      SCOPED_TRACE(name);
      room_reverb::test::ReflectionScore score;
      double direct_confidence_min = 1.0;
      for (std::size_t i = 0; i < reflectionRoomCount(set); ++i) {
        const auto room = reflectionRoom(set, i);
        EarlyReflectionOptions options;
        options.onset_method = method;
        options.direct_distance_m = kC * room.images.front().time_s;
        const auto estimate = estimateEarlyReflections(room.ambix, options);
        direct_confidence_min = std::min(direct_confidence_min, estimate.front().confidence.value_or(-1.0));
        EXPECT_NEAR(estimate.front().distance_m, *options.direct_distance_m, 1e-9);
        score.add(room_reverb::test::scoreReflections(room, estimate));
      }
      ASSERT_GE(score.found, 10);
      // The confidence against the direction's error: those pointed within 3 degrees, and
      // those off by more than 10; and how well the confident ones are placed.
      std::vector<double> sharp, off, confident_errors, well_pointed_errors;
      for (std::size_t k = 0; k < score.found_confidence.size(); ++k) {
        if (score.direction_error_deg[k] <= 3.0) sharp.push_back(score.found_confidence[k]);
        if (score.direction_error_deg[k] > 10.0) off.push_back(score.found_confidence[k]);
        if (score.found_confidence[k] >= 0.95) confident_errors.push_back(score.direction_error_deg[k]);
        if (score.direction_error_deg[k] <= 3.0) well_pointed_errors.push_back(score.image_source_error_m[k]);
      }
      const double p50 = quantileLinear(score.image_source_error_m, 0.5);
      std::printf("[ stats    ] %s: %s; image-source error median %.3f m (within 3 deg: p95 %.3f m); "
                  "confidence median %.3f where the direction is within 3 deg (%zu), %.3f where it is off by more "
                  "than 10 (%zu); direction p95 of those with confidence >= 0.95: %.1f deg (%zu); direct sound's "
                  "min %.3f\n",
                  name.c_str(), score.summary().c_str(), p50, quantileLinear(well_pointed_errors, 0.95), median(sharp),
                  sharp.size(), median(off), off.size(), quantileLinear(confident_errors, 0.95),
                  confident_errors.size(), direct_confidence_min);
      // Placement adds no error of its own: where the direction is within 3 degrees (5 cm a
      // metre) and the time within the match's 0.5 ms (17 cm), the image source is too.
      ASSERT_GE(well_pointed_errors.size(), 10u);
      EXPECT_LT(quantileLinear(well_pointed_errors, 0.95), 0.05 * 15.0 + 0.17);
      EXPECT_GT(direct_confidence_min, 0.9);
      // The confidence says what it should: high where the direction is right, and the
      // confident ones are pointed well.
      EXPECT_GT(median(sharp), 0.9);
      EXPECT_LT(quantileLinear(confident_errors, 0.95), method == OnsetMethod::kGroupDelay ? 10.0 : 3.0);
      if (method == OnsetMethod::kMatchedPursuit) {
        EXPECT_LT(quantileLinear(score.direction_error_deg, 0.95), 3.0);
        EXPECT_LE(off.size(), 1u);
      } else {
        // ...and lower where it is wrong.
        ASSERT_GE(off.size(), 3u);
        EXPECT_LT(median(off), median(sharp) - 0.1);
      }
    }
  }
}

TEST(ReflectionImageSources, AGivenSourceDistanceCancelsTheMeasurementsLatency) {
  const auto room = reflectionRoom(ReflectionRoomSet::kDevelopment, 0);
  // The same RIR recorded 2 ms late, as a measurement system's latency would put it.
  AudioBuffer late = room.ambix;
  const std::size_t latency = 96;
  for (auto& channel : late.channels) channel.insert(channel.begin(), latency, 0.0f);
  const double true_direct_m = kC * room.images.front().time_s;

  EarlyReflectionOptions given;
  given.direct_distance_m = true_direct_m;
  const auto on_time = estimateEarlyReflections(room.ambix, given);
  const auto delayed_given = estimateEarlyReflections(late, given);
  const auto delayed_guessed = estimateEarlyReflections(late);
  ASSERT_EQ(on_time.size(), delayed_given.size());
  ASSERT_EQ(on_time.size(), delayed_guessed.size());
  for (std::size_t k = 0; k < on_time.size(); ++k) {
    EXPECT_NEAR(delayed_given[k].time_of_arrival_s - on_time[k].time_of_arrival_s, 0.002, 1e-6) << k;
    // With the source's distance given, every image source stays where it is...
    EXPECT_LT((position(delayed_given[k]) - position(on_time[k])).norm(), 1e-3) << k;
    // ...without it, each moves out by c times the latency.
    EXPECT_NEAR(delayed_guessed[k].distance_m - on_time[k].distance_m, kC * 0.002, 1e-3) << k;
  }
  EXPECT_NEAR(delayed_given.front().distance_m, true_direct_m, 1e-9);

  EarlyReflectionOptions bad;
  bad.direct_distance_m = -1.0;
  EXPECT_THROW(estimateEarlyReflections(room.ambix, bad), InputError);
}
