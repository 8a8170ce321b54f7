// The RSAO of a capture point moved to listeners elsewhere in the room
// (rsao/listener_translation.h), against the truth of the synthetic rooms of
// reflection_rooms.h heard at the new positions: first with the rooms' exact image sources
// as the RSAO (the geometry alone), then with the estimator's RSAO. The held-out rooms
// (other seeds and shapes, a reflector panel) are only scored, in the report.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "reflection_rooms.h"
#include "reflection_score.h"
#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/quantile.h"
#include "room_reverb/rsao/late_envelope.h"
#include "room_reverb/rsao/listener_translation.h"
#include "room_reverb/rsao/onset_ramp_fit.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/rsao/rsao_estimator.h"
#include "room_reverb/rsao/rsao_resynthesis.h"

using namespace room_reverb::core;
using room_reverb::test::ImageArrival;
using room_reverb::test::ReflectionRoom;
using room_reverb::test::ReflectionRoomGeometry;
using room_reverb::test::ReflectionRoomSet;
using room_reverb::test::ReflectionScore;
using room_reverb::test::reflectionRoom;
using room_reverb::test::reflectionRoomCount;
using room_reverb::test::scoreReflections;

namespace {

constexpr double kC = 343.0;  // the rooms' speed of sound, and the estimator's default
constexpr double kPi = 3.14159265358979323846;

RoomModel modelOf(const ReflectionRoomGeometry& g) { return room_reverb::test::roomModelOf(g); }

EarlyReflection reflectionOf(const ImageArrival& a) {
  EarlyReflection r;
  r.time_of_arrival_s = a.time_s;
  r.level = a.level;
  r.azimuth_rad = std::atan2(a.direction.y(), a.direction.x());
  r.elevation_rad = std::asin(a.direction.z());
  r.distance_m = kC * a.time_s;
  return r;
}

// The room's own image arrivals up to `max_order` as an RSAO: exact times, directions,
// levels and distances.
Rsao exactRsao(const ReflectionRoom& room, int max_order = 2) {
  Rsao rsao;
  for (const ImageArrival& a : room.images) {
    if (a.order <= max_order) rsao.reflections.push_back(reflectionOf(a));
  }
  return rsao;
}

Eigen::Vector3d directionOf(const EarlyReflection& r) {
  return {std::cos(r.elevation_rad) * std::cos(r.azimuth_rad), std::cos(r.elevation_rad) * std::sin(r.azimuth_rad),
          std::sin(r.elevation_rad)};
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

// A walking listener's steps from the capture point: `count` horizontal offsets of
// 0.5-2 m (height within +-0.2 m) that keep the listener 0.5 m from the walls and 1 m
// from the source, on the source's side of a panel. Deterministic per room.
std::vector<Eigen::Vector3d> listenerOffsets(const ReflectionRoomGeometry& g, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  for (int attempt = 0; attempt < 2000 && out.size() < count; ++attempt) {
    const double azimuth = 2.0 * kPi * unit(rng), distance = 0.5 + 1.5 * unit(rng);
    const Eigen::Vector3d offset(distance * std::cos(azimuth), distance * std::sin(azimuth), 0.4 * unit(rng) - 0.2);
    const Eigen::Vector3d p = g.receiver_m + offset;
    if ((p.array() < 0.5).any() || ((g.size_m - p).array() < 0.5).any()) continue;
    if ((p - g.source_m).norm() < 1.0) continue;
    if (g.panel && p.x() > g.panel->x_m - 0.3) continue;
    out.push_back(offset);
  }
  return out;
}

// Found reflections within 0.1 ms and 5 degrees of the truth (the scoring's "found" is by
// time alone, within 0.5 ms).
int withinBoth(const ReflectionScore& s) {
  int n = 0;
  for (std::size_t i = 0; i < s.toa_error_ms.size(); ++i) {
    n += std::abs(s.toa_error_ms[i]) <= 0.1 && s.direction_error_deg[i] <= 5.0;
  }
  return n;
}

// Early energy per octave 125 Hz-4 kHz (W, from 1 ms before the direct sound to 50 ms
// after it) and the direct-to-reverberant ratio (W energy up to 2.5 ms after the direct
// sound over the rest) of a first-order AmbiX RIR, in dB.
struct EarlyLevels {
  std::vector<double> early_db;
  double drr_db = 0.0;
  double direct_db = 0.0, rest_db = 0.0;  // the DRR's two parts
  double after_50ms_db = 0.0;             // W's energy from 50 ms after the direct sound
};

EarlyLevels earlyLevels(const AudioBuffer& ambix, double direct_s) {
  static const BandFilterBank bank = [] {
    std::vector<FrequencyBand> bands;
    for (const FrequencyBand& b : standardBands(BandResolution::kOctave)) {
      if (b.nominal_hz >= 125.0 && b.nominal_hz <= 4000.0) bands.push_back(b);
    }
    return BandFilterBank(bands, 48000.0);
  }();
  const std::vector<float>& w = ambix.channels[0];
  const auto at = [&](double t) { return std::min(w.size(), static_cast<std::size_t>(std::max(0.0, t) * 48000.0)); };
  EarlyLevels levels;
  for (const std::vector<float>& band : bank.split(w)) {
    double e = 0.0;
    for (std::size_t n = at(direct_s - 0.001); n < at(direct_s + 0.050); ++n) e += static_cast<double>(band[n]) * band[n];
    levels.early_db.push_back(10.0 * std::log10(e + 1e-30));
  }
  double direct = 0.0, rest = 0.0, after_50ms = 0.0;
  for (std::size_t n = 0; n < w.size(); ++n) {
    (n < at(direct_s + 0.0025) ? direct : rest) += static_cast<double>(w[n]) * w[n];
    if (n >= at(direct_s + 0.050)) after_50ms += static_cast<double>(w[n]) * w[n];
  }
  levels.after_50ms_db = 10.0 * std::log10(after_50ms);
  levels.drr_db = 10.0 * std::log10(direct / rest);
  levels.direct_db = 10.0 * std::log10(direct);
  levels.rest_db = 10.0 * std::log10(rest);
  return levels;
}

// Each RSAO's levels are the mean energy over resynthesis seeds 1..N (ROOM_REVERB_LEVEL_SEEDS,
// default 1): the late part's noise in a 50 ms window at 125 Hz has about nine degrees of
// freedom, and one draw moves its energy by a few dB.
EarlyLevels meanEarlyLevels(const Rsao& rsao, double duration_s) {
  const char* env = std::getenv("ROOM_REVERB_LEVEL_SEEDS");
  const int seeds = env != nullptr ? std::max(1, std::atoi(env)) : 1;
  std::vector<double> early;
  double drr = 0.0, direct = 0.0, rest = 0.0, after = 0.0;
  for (int seed = 1; seed <= seeds; ++seed) {
    ResynthesisOptions options;
    options.duration_s = duration_s;
    options.seed = static_cast<std::uint32_t>(seed);
    const EarlyLevels one = earlyLevels(resynthesizeRsao(rsao, options), rsao.reflections.front().time_of_arrival_s);
    if (early.empty()) early.assign(one.early_db.size(), 0.0);
    for (std::size_t b = 0; b < early.size(); ++b) early[b] += std::pow(10.0, one.early_db[b] / 10.0) / seeds;
    drr += one.drr_db / seeds;
    direct += one.direct_db / seeds;
    rest += one.rest_db / seeds;
    after += one.after_50ms_db / seeds;
  }
  EarlyLevels mean;
  for (double e : early) mean.early_db.push_back(10.0 * std::log10(e));
  mean.drr_db = drr;
  mean.direct_db = direct;
  mean.rest_db = rest;
  mean.after_50ms_db = after;
  return mean;
}

// The differences heard - truth per octave band and of the DRR, dB, appended to `early`
// and `drr`; ROOM_REVERB_PRINT_DRR_PARTS=1 prints the DRR's parts against `truth_name`.
void appendLevelErrors(const EarlyLevels& heard, const EarlyLevels& truth, const char* truth_name,
                       std::vector<double>& early, std::vector<double>& drr) {
  for (std::size_t b = 0; b < truth.early_db.size(); ++b) early.push_back(heard.early_db[b] - truth.early_db[b]);
  drr.push_back(heard.drr_db - truth.drr_db);
  if (std::getenv("ROOM_REVERB_PRINT_DRR_PARTS")) {
    std::printf("      DRR parts against %s: direct %+.2f dB, rest %+.2f dB, after 50 ms %+.2f dB\n", truth_name,
                heard.direct_db - truth.direct_db, heard.rest_db - truth.rest_db,
                heard.after_50ms_db - truth.after_50ms_db);
  }
}

// Level errors of an RSAO against the RIR at its position.
void addLevelErrors(const Rsao& rsao, const ReflectionRoom& there, std::vector<double>& early, std::vector<double>& drr) {
  appendLevelErrors(meanEarlyLevels(rsao, there.ambix.durationS()),
                    earlyLevels(there.noiseless, there.images.front().time_s), "the room", early, drr);
}

// Level errors of an RSAO against another RSAO, both resynthesised (the check:
// the moved RSAO against the one estimated from the new position's own RIR).
void addLevelErrors(const Rsao& rsao, const Rsao& reference, double duration_s, std::vector<double>& early,
                    std::vector<double>& drr) {
  appendLevelErrors(meanEarlyLevels(rsao, duration_s), meanEarlyLevels(reference, duration_s), "its own RSAO", early,
                    drr);
}

struct MovedScore {
  ReflectionScore moved, still, own;  // vs the truth at the new position
  // Level errors at the new positions, dB: early energy per octave and DRR, of the moved
  // RSAO and of the RSAO left at the capture point.
  std::vector<double> moved_early_db, moved_drr_db, still_early_db, still_drr_db;
  // The moved RSAO against the RSAO estimated from the new position's own RIR.
  std::vector<double> versus_own_early_db, versus_own_drr_db;
  // The floor: the RSAO against the RIR it was estimated from, at the capture point; and
  // the translation's own RSAO there (its completed reflections and its late part).
  std::vector<double> capture_early_db, capture_drr_db, rig_early_db, rig_drr_db;
  int surface = 0, unmatched = 0, modelled = 0;  // the reflections at the capture point, by anchor

  void add(const MovedScore& o) {
    moved.add(o.moved);
    still.add(o.still);
    own.add(o.own);
    for (auto [to, from] : {std::pair{&moved_early_db, &o.moved_early_db}, std::pair{&moved_drr_db, &o.moved_drr_db},
                            std::pair{&still_early_db, &o.still_early_db}, std::pair{&still_drr_db, &o.still_drr_db},
                            std::pair{&capture_early_db, &o.capture_early_db},
                            std::pair{&capture_drr_db, &o.capture_drr_db}, std::pair{&rig_early_db, &o.rig_early_db},
                            std::pair{&rig_drr_db, &o.rig_drr_db}, std::pair{&versus_own_early_db, &o.versus_own_early_db},
                            std::pair{&versus_own_drr_db, &o.versus_own_drr_db}}) {
      to->insert(to->end(), from->begin(), from->end());
    }
    surface += o.surface;
    unmatched += o.unmatched;
    modelled += o.modelled;
  }
  double withinShare() const { return moved.found > 0 ? static_cast<double>(withinBoth(moved)) / moved.found : 1.0; }
};

// The estimator's RSAO at the capture point moved to each listener offset, scored against
// the truth there; beside it the RSAO left where it was measured, and the estimator's own
// RSAO of the RIR at the new position.
MovedScore scoreMovedRoom(ReflectionRoomSet set, std::size_t index, std::size_t offsets, bool levels = false,
                          const RsaoOptions& estimation = {}) {
  const ReflectionRoom capture = reflectionRoom(set, index);
  const Rsao measured = estimateRsao(capture.ambix, AmbisonicFormat::kAmbiX, estimation);
  // The report's completion order can be set (ROOM_REVERB_COMPLETE_ORDER, 0: none) to
  // measure what the room model's completion adds.
  ListenerTranslationOptions options;
  if (const char* order = std::getenv("ROOM_REVERB_COMPLETE_ORDER")) options.complete_order = std::atoi(order);
  const ListenerTranslation translation(measured, capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                        modelOf(capture.geometry), options);
  MovedScore score;
  for (std::size_t k = 1; k < translation.anchors().size(); ++k) {
    const ReflectionAnchor anchor = translation.anchors()[k].anchor;
    score.surface += anchor == ReflectionAnchor::kSurface;
    score.unmatched += anchor == ReflectionAnchor::kUnmatched;
    score.modelled += anchor == ReflectionAnchor::kModelled;
  }
  if (levels) {
    addLevelErrors(measured, capture, score.capture_early_db, score.capture_drr_db);
    addLevelErrors(translation.at(capture.geometry.receiver_m), capture, score.rig_early_db, score.rig_drr_db);
  }
  for (const Eigen::Vector3d& offset : listenerOffsets(capture.geometry, offsets, 1000 + static_cast<std::uint32_t>(index))) {
    const ReflectionRoom there = reflectionRoom(set, index, offset);
    MovedScore one;
    const Rsao moved = translation.at(there.geometry.receiver_m);
    one.moved = scoreReflections(there, moved.reflections);
    if (levels) {
      addLevelErrors(moved, there, one.moved_early_db, one.moved_drr_db);
      addLevelErrors(measured, there, one.still_early_db, one.still_drr_db);
    }
    one.still = scoreReflections(there, measured.reflections);
    const Rsao own = estimateRsao(there.ambix, AmbisonicFormat::kAmbiX, estimation);
    one.own = scoreReflections(there, own.reflections);
    if (levels) addLevelErrors(moved, own, there.ambix.durationS(), one.versus_own_early_db, one.versus_own_drr_db);
    score.add(one);
  }
  return score;
}

std::string describe(const MovedScore& s) {
  const auto line = [&](const char* what, const ReflectionScore& r) {
    char text[400];
    std::snprintf(text, sizeof text, "  %-30s %s; within 0.1 ms and 5 deg: %d of %d resolvable\n", what,
                  r.summary().c_str(), withinBoth(r), r.resolvable);
    return std::string(text);
  };
  char anchors[200];
  std::snprintf(anchors, sizeof anchors,
                "  reflections at the capture point: measured on a surface %d, measured unmatched %d, modelled %d",
                s.surface, s.unmatched, s.modelled);
  std::string text = line("moved:", s.moved) + line("left at the capture point:", s.still) +
                     line("estimated at the new position:", s.own) + anchors;
  const auto levels = [](const char* what, const std::vector<double>& early, const std::vector<double>& drr) {
    if (early.empty()) return std::string();
    std::vector<double> abs_early, abs_drr;
    for (double v : early) abs_early.push_back(std::abs(v));
    for (double v : drr) abs_drr.push_back(std::abs(v));
    const auto within = [](const std::vector<double>& v) {
      return 100.0 * static_cast<double>(std::count_if(v.begin(), v.end(), [](double x) { return x <= 1.0; })) /
             static_cast<double>(v.size());
    };
    char text[400];
    std::snprintf(text, sizeof text,
                  "\n  %-30s early energy per octave 125 Hz-4 kHz: |error| median %.2f dB, p90 %.2f dB, %.0f %% within 1 dB, "
                  "signed median %+.2f dB; DRR: |error| median %.2f dB, p90 %.2f dB, %.0f %% within 1 dB, signed median %+.2f dB",
                  what, quantileLinear(abs_early, 0.5), quantileLinear(abs_early, 0.9), within(abs_early),
                  quantileLinear(early, 0.5), quantileLinear(abs_drr, 0.5), quantileLinear(abs_drr, 0.9), within(abs_drr),
                  quantileLinear(drr, 0.5));
    // The signed median by octave (the errors run band by band, six to an RIR).
    std::string by_band = "; by octave 125 Hz-4 kHz, signed median:";
    for (std::size_t b = 0; b < 6; ++b) {
      std::vector<double> band;
      for (std::size_t i = b; i < early.size(); i += 6) band.push_back(early[i]);
      char one[16];
      std::snprintf(one, sizeof one, " %+.2f", quantileLinear(band, 0.5));
      by_band += one;
    }
    std::string within_band = "; within 1 dB by octave:";
    for (std::size_t b = 0; b < 6; ++b) {
      std::vector<double> band;
      for (std::size_t i = b; i < early.size(); i += 6) band.push_back(std::abs(early[i]));
      char one[16];
      std::snprintf(one, sizeof one, " %.0f", within(band));
      within_band += one;
    }
    return std::string(text) + by_band + " dB" + within_band + " %";
  };
  return text + levels("levels at the capture point:", s.capture_early_db, s.capture_drr_db) +
         levels("translated to the capture point:", s.rig_early_db, s.rig_drr_db) +
         levels("levels, moved:", s.moved_early_db, s.moved_drr_db) +
         levels("moved against own RSAO there:", s.versus_own_early_db, s.versus_own_drr_db) +
         levels("levels, left at the capture:", s.still_early_db, s.still_drr_db);
}

TEST(ListenerTranslation, ExactImageSourcesMoveToTheTruthAtTheNewPosition) {
  for (std::size_t index : {0u, 3u, 8u}) {  // shoeboxes and a dull room
    const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, index);
    const Rsao exact = exactRsao(capture);
    for (const bool with_model : {true, false}) {
      const std::optional<RoomModel> model = with_model ? std::optional<RoomModel>(modelOf(capture.geometry)) : std::nullopt;
      const ListenerTranslation translation(exact, capture.geometry.receiver_m, Eigen::Quaterniond::Identity(), model);
      // Every image up to second order is measured here: nothing is left to complete.
      ASSERT_EQ(translation.anchors().size(), exact.reflections.size());
      for (std::size_t k = 1; k < translation.anchors().size(); ++k) {
        EXPECT_EQ(translation.anchors()[k].anchor, with_model ? ReflectionAnchor::kSurface : ReflectionAnchor::kUnchecked)
            << capture.name << " reflection " << k;
      }
      for (const Eigen::Vector3d& offset : listenerOffsets(capture.geometry, 3, 7)) {
        const ReflectionRoom there = reflectionRoom(ReflectionRoomSet::kDevelopment, index, offset);
        const Rsao moved = translation.at(there.geometry.receiver_m);
        const Rsao truth = exactRsao(there);
        ASSERT_EQ(moved.reflections.size(), truth.reflections.size()) << capture.name;
        for (std::size_t k = 0; k < truth.reflections.size(); ++k) {
          const EarlyReflection& m = moved.reflections[k];
          const EarlyReflection& t = truth.reflections[k];
          EXPECT_NEAR(m.time_of_arrival_s, t.time_of_arrival_s, 1e-7) << capture.name << " arrival " << k;
          EXPECT_LT(angleDeg(directionOf(m), directionOf(t)), 0.01) << capture.name << " arrival " << k;
          EXPECT_NEAR(m.level / t.level, 1.0, 1e-3) << capture.name << " arrival " << k;
          EXPECT_NEAR(m.distance_m, t.distance_m, 1e-6);
        }
      }
    }
  }
}

TEST(ListenerTranslation, AMatchedReflectionNamesItsSurfaces) {
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, 0);
  const ListenerTranslation translation(exactRsao(capture, 1), capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                        modelOf(capture.geometry));
  // A first-order image lies beyond the wall it stands for: its coordinate outside the box
  // names the wall.
  const Eigen::Vector3d size = capture.geometry.size_m;
  const std::size_t measured = translation.measured().reflections.size();
  for (std::size_t k = 1; k < translation.anchors().size(); ++k) {
    const AnchoredReflection& a = translation.anchors()[k];
    // The second-order images of these walls are completed from the model.
    EXPECT_EQ(a.anchor, k < measured ? ReflectionAnchor::kSurface : ReflectionAnchor::kModelled);
    if (k >= measured) {
      EXPECT_EQ(a.planes.size(), 2u);
      continue;
    }
    ASSERT_EQ(a.planes.size(), 1u);
    std::string expected;
    if (a.image_source_m.z() < 0.0) expected = "floor";
    if (a.image_source_m.z() > size.z()) expected = "ceiling";
    if (a.image_source_m.x() < 0.0) expected = "wall_x_min";
    if (a.image_source_m.x() > size.x()) expected = "wall_x_max";
    if (a.image_source_m.y() < 0.0) expected = "wall_y_min";
    if (a.image_source_m.y() > size.y()) expected = "wall_y_max";
    EXPECT_EQ(a.surfaces, expected) << "reflection " << k;
    EXPECT_LT(std::abs(a.path_error_m), 1e-9);
    EXPECT_LT(a.angle_error_deg, 1e-4);
  }
}

TEST(ListenerTranslation, TheRoomModelCompletesSecondOrderReflectionsFromTheMeasuredWalls) {
  // Only the direct sound and the six first-order reflections measured: the second-order
  // images come from the model, their levels from the walls' measured reflection factors.
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, 0);
  const ListenerTranslation translation(exactRsao(capture, 1), capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                        modelOf(capture.geometry));
  const Eigen::Vector3d offset = listenerOffsets(capture.geometry, 1, 11).front();
  const ReflectionRoom there = reflectionRoom(ReflectionRoomSet::kDevelopment, 0, offset);
  const Rsao moved = translation.at(there.geometry.receiver_m);
  const Rsao truth = exactRsao(there, 2);
  ASSERT_EQ(moved.reflections.size(), truth.reflections.size());
  for (std::size_t k = 0; k < truth.reflections.size(); ++k) {
    EXPECT_NEAR(moved.reflections[k].time_of_arrival_s, truth.reflections[k].time_of_arrival_s, 1e-7) << k;
    EXPECT_LT(angleDeg(directionOf(moved.reflections[k]), directionOf(truth.reflections[k])), 0.01) << k;
    EXPECT_NEAR(moved.reflections[k].level / truth.reflections[k].level, 1.0, 1e-3) << k;
  }
  ListenerTranslationOptions measured_only;
  measured_only.complete_order = 0;
  const ListenerTranslation plain(exactRsao(capture, 1), capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                  modelOf(capture.geometry), measured_only);
  EXPECT_EQ(plain.at(there.geometry.receiver_m).reflections.size(), 7u);
}

TEST(ListenerTranslation, AMissedFirstOrderReflectionIsCompletedAsTheTypicalWall) {
  // One first-order reflection left out of the measured RSAO (the estimator missed it): the
  // model adds it at its true time and direction, its level from the median of the other
  // walls' measured reflection factors, and the second-order images off that wall stay out
  // (their factor would be a guess twice over).
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, 0);
  Rsao measured = exactRsao(capture, 1);
  ASSERT_EQ(measured.reflections.size(), 7u);
  const EarlyReflection missed = measured.reflections[3];
  measured.reflections.erase(measured.reflections.begin() + 3);
  const double reach = measured.reflections[0].level * measured.reflections[0].distance_m;
  std::vector<double> factors;
  for (std::size_t k = 1; k < measured.reflections.size(); ++k) {
    factors.push_back(measured.reflections[k].level * measured.reflections[k].distance_m / reach);
  }
  std::sort(factors.begin(), factors.end());
  const double typical = factors[factors.size() / 2];
  const ListenerTranslation translation(measured, capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                        modelOf(capture.geometry));
  int first_order_completed = 0;
  for (std::size_t k = 0; k < translation.anchors().size(); ++k) {
    const AnchoredReflection& a = translation.anchors()[k];
    if (a.anchor != ReflectionAnchor::kModelled) continue;
    const EarlyReflection& r = translation.reflectionsAtRig()[k];
    if (a.planes.size() == 1) {
      ++first_order_completed;
      EXPECT_NEAR(r.time_of_arrival_s, missed.time_of_arrival_s, 1e-7);
      EXPECT_LT(angleDeg(directionOf(r), directionOf(missed)), 0.01);
      EXPECT_NEAR(r.level, typical * reach / r.distance_m, 1e-9 * r.level);
    }
  }
  EXPECT_EQ(first_order_completed, 1);
  // Only the first order completed, when asked; the other walls' second-order images
  // besides it by default.
  ListenerTranslationOptions first_only;
  first_only.complete_order = 1;
  const ListenerTranslation only_first(measured, capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                       modelOf(capture.geometry), first_only);
  EXPECT_EQ(only_first.reflectionsAtRig().size(), 7u);
  EXPECT_GT(translation.reflectionsAtRig().size(), 7u);
}

TEST(ListenerTranslation, AReflectionIsGoneWhereItsPointLeavesThePanel) {
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kHeldOut, 9);  // a reflector room
  ASSERT_TRUE(capture.geometry.panel.has_value()) << capture.name;
  const ReflectionRoomGeometry& g = capture.geometry;
  const Eigen::Vector3d panel_image(2.0 * g.panel->x_m - g.source_m.x(), g.source_m.y(), g.source_m.z());
  const ListenerTranslation with_model(exactRsao(capture), g.receiver_m, Eigen::Quaterniond::Identity(), modelOf(g));
  const ListenerTranslation without_model(exactRsao(capture), g.receiver_m, Eigen::Quaterniond::Identity(), std::nullopt);
  // Is the panel's reflection among the arrivals of an RSAO heard at `listener`?
  const auto holdsPanelReflection = [&](const Rsao& rsao, const Eigen::Vector3d& listener) {
    const double toa = (panel_image - listener).norm() / kC;
    for (std::size_t k = 1; k < rsao.reflections.size(); ++k) {
      if (std::abs(rsao.reflections[k].time_of_arrival_s - toa) < 1e-6) return true;
    }
    return false;
  };
  int stays = 0, leaves = 0;
  for (double dy = -3.0; dy <= 3.0; dy += 0.25) {
    const Eigen::Vector3d offset(-0.2, dy, 0.0);
    ReflectionRoom there;
    try {
      there = reflectionRoom(ReflectionRoomSet::kHeldOut, 9, offset);
    } catch (const std::invalid_argument&) {
      continue;
    }
    // The truth holds the panel's image only where its reflection point is on the panel.
    const bool truth = holdsPanelReflection(exactRsao(there), there.geometry.receiver_m);
    EXPECT_EQ(holdsPanelReflection(with_model.at(there.geometry.receiver_m), there.geometry.receiver_m), truth)
        << "listener moved by " << dy << " m along y";
    EXPECT_TRUE(holdsPanelReflection(without_model.at(there.geometry.receiver_m), there.geometry.receiver_m));
    (truth ? stays : leaves) += 1;
  }
  EXPECT_GE(stays, 2);
  EXPECT_GE(leaves, 2);
}

TEST(ListenerTranslation, HeardPathsRunThroughTheirReflectionPointsOnTheWalls) {
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, 0);
  const ListenerTranslation translation(exactRsao(capture, 1), capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                        modelOf(capture.geometry));
  const Eigen::Vector3d offset = listenerOffsets(capture.geometry, 1, 11).front();
  const Eigen::Vector3d listener = capture.geometry.receiver_m + offset;
  const Eigen::Vector3d size = capture.geometry.size_m;
  const std::vector<HeardReflection> heard = translation.reflectionsAt(listener);
  const std::vector<ReflectionPath> paths = translation.heardPathsAt(listener);
  ASSERT_EQ(paths.size(), static_cast<std::size_t>(std::count_if(heard.begin(), heard.end(), [](const HeardReflection& h) {
              return h.heard;
            })));
  ASSERT_FALSE(paths.empty());
  EXPECT_EQ(paths.front().anchor, ReflectionAnchor::kSource);
  ASSERT_EQ(paths.front().points.size(), 2u);
  EXPECT_LT((paths.front().points.front() - capture.geometry.source_m).norm(), 1e-6);
  for (const ReflectionPath& path : paths) {
    const EarlyReflection& r = heard[path.index].reflection;
    EXPECT_EQ(path.level, r.level);
    // From the source, through one point on a face of the box per order, to the listener;
    // its length is the reflection's distance.
    ASSERT_EQ(path.points.size(), translation.anchors()[path.index].planes.size() + 2) << path.index;
    EXPECT_LT((path.points.back() - listener).norm(), 1e-12);
    double length = 0.0;
    for (std::size_t i = 1; i < path.points.size(); ++i) length += (path.points[i] - path.points[i - 1]).norm();
    EXPECT_NEAR(length, r.distance_m, 1e-6) << path.index;
    for (std::size_t i = 1; i + 1 < path.points.size(); ++i) {
      const Eigen::Vector3d& p = path.points[i];
      const double to_face = std::min({p.x(), p.y(), p.z(), size.x() - p.x(), size.y() - p.y(), size.z() - p.z()});
      EXPECT_LT(std::abs(to_face), 1e-6) << "reflection " << path.index << ", point " << i;
    }
  }
}

// A 7 x 5 x 3 m room with a 1.6 m tall cabinet between the source and the far side: the
// RSAO is the direct sound alone, measured in view of the source.
struct CabinetRoom {
  RoomModel model;
  Eigen::Vector3d source{1.5, 2.5, 1.4};
  Eigen::Vector3d rig{3.0, 1.0, 1.4};
  Rsao rsao;
};

CabinetRoom cabinetRoom() {
  CabinetRoom room;
  room.model.size_m = {7.0, 5.0, 3.0};
  for (const char* name : kRoomSurfaceNames) room.model.surfaces[name] = SurfaceAssignment{"plaster_smooth", 1.0};
  room.model.rig_position_m = room.rig;
  CuboidObject cabinet;
  cabinet.label = "cabinet";
  cabinet.material = "wood";
  cabinet.center_m = {3.5, 2.5, 0.8};
  cabinet.size_m = {0.6, 1.2, 1.6};
  room.model.objects.push_back(cabinet);
  EarlyReflection direct;
  const Eigen::Vector3d to_source = room.source - room.rig;
  direct.distance_m = to_source.norm();
  direct.time_of_arrival_s = direct.distance_m / kC;
  direct.level = 1.0 / direct.distance_m;
  direct.azimuth_rad = std::atan2(to_source.y(), to_source.x());
  direct.elevation_rad = std::asin(to_source.z() / to_source.norm());
  room.rsao.reflections.push_back(direct);
  return room;
}

TEST(ListenerTranslation, TheDirectSoundBendsAroundAnObjectAsTheSimulatedRouteHearsIt) {
  // Behind the cabinet the moved direct sound comes around its edge as the simulated
  // route's image sources bring it (edge_diffraction.h): the same delay, the same
  // direction, and the power mean of their octave gains 125 Hz-4 kHz as its level; the
  // path drawn for it turns at the edge.
  const CabinetRoom room = cabinetRoom();
  ListenerTranslationOptions options;
  options.speed_of_sound_m_s = kC;
  const ListenerTranslation translation(room.rsao, room.rig, Eigen::Quaterniond::Identity(), room.model, options);
  const AcousticScene scene = roomModelToScene(room.model, MaterialLibrary::loadDefault());
  PropagationModel free_field;
  free_field.speed_of_sound_m_s = kC;
  free_field.air_attenuation_per_m.fill(0.0);
  ImageSourceOptions search;
  search.max_order = 0;
  int behind = 0;
  for (const Eigen::Vector3d& listener : {Eigen::Vector3d(5.5, 2.5, 1.2), Eigen::Vector3d(5.0, 2.0, 1.0),
                                           Eigen::Vector3d(5.5, 3.2, 1.5), Eigen::Vector3d(5.5, 1.0, 1.4)}) {
    SCOPED_TRACE(listener.transpose());
    const std::vector<SpecularPath> paths = computeImageSources(scene, room.source, listener, free_field, search);
    ASSERT_EQ(paths.size(), 1u);
    const SpecularPath& truth = paths.front();
    const HeardReflection moved = translation.reflectionsAt(listener).front();
    ASSERT_TRUE(moved.heard);
    EXPECT_NEAR(moved.reflection.time_of_arrival_s, truth.delay_s, 1e-9);
    EXPECT_LT(angleDeg(directionOf(moved.reflection), truth.arrival_direction), 1e-6);
    // Per octave 125 Hz-4 kHz: the level times the low-pass's response against the image
    // source's gain; their power over those bands alike, each band within 2.5 dB, and a
    // better fit than the level alone where the edge's loss rises with frequency.
    const double p = moved.lowpass_pole;
    ASSERT_GE(p, 0.0);
    ASSERT_LT(p, 1.0);
    double power = 0.0, moved_power = 0.0, worst_db = 0.0, flat_worst_db = 0.0;
    std::vector<double> truth_db;
    for (int b = 1; b <= 6; ++b) {
      const double f = standardBands(BandResolution::kOctave)[static_cast<std::size_t>(b)].center_hz;
      const double w = 2.0 * kPi * f / 48000.0;
      const double response = (1.0 - p) / std::sqrt(1.0 - 2.0 * p * std::cos(w) + p * p);
      const double g = std::abs(truth.pressure_gain[static_cast<std::size_t>(b)]);
      power += g * g;
      moved_power += std::pow(moved.reflection.level * response, 2);
      worst_db = std::max(worst_db, std::abs(20.0 * std::log10(moved.reflection.level * response / g)));
      truth_db.push_back(20.0 * std::log10(g));
    }
    EXPECT_NEAR(10.0 * std::log10(moved_power / power), 0.0, 0.01);
    EXPECT_LT(worst_db, 2.5);
    const double flat_db = 10.0 * std::log10(power / 6.0);
    for (double t : truth_db) flat_worst_db = std::max(flat_worst_db, std::abs(t - flat_db));
    EXPECT_LE(worst_db, flat_worst_db + 1e-9);
    const bool shadowed = truth.distance_m > (listener - room.source).norm() + 1e-9;
    behind += shadowed ? 1 : 0;
    const std::vector<ReflectionPath> drawn = translation.heardPathsAt(listener);
    ASSERT_FALSE(drawn.empty());
    // Straight, or over one edge or two (across a face); as long as the arrival's path.
    const std::vector<Eigen::Vector3d>& points = drawn.front().points;
    EXPECT_EQ(points.size() > 2, shadowed);
    double length = 0.0;
    for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
    EXPECT_NEAR(length, moved.reflection.distance_m, 1e-9);
  }
  EXPECT_GE(behind, 3);
  // Well behind it the direct sound is more than 10 dB down on the free field's 1/r, and
  // duller: the low-pass is set, and the moved RSAO carries it as one more section.
  const Eigen::Vector3d deep(5.5, 2.5, 0.6);
  const HeardReflection deep_direct = translation.reflectionsAt(deep).front();
  const double pole = deep_direct.lowpass_pole;
  EXPECT_GT(pole, 0.1);
  double deep_power = 0.0;
  for (int b = 1; b <= 6; ++b) {
    const double w = 2.0 * kPi * standardBands(BandResolution::kOctave)[static_cast<std::size_t>(b)].center_hz / 48000.0;
    deep_power += std::pow(deep_direct.reflection.level, 2) * (1.0 - pole) * (1.0 - pole) /
                  (1.0 - 2.0 * pole * std::cos(w) + pole * pole) / 6.0;
  }
  EXPECT_LT(10.0 * std::log10(deep_power * (deep - room.source).squaredNorm()), -10.0);
  const Rsao moved_rsao = translation.at(deep);
  const EarlyReflection& carried = moved_rsao.reflections.front();
  ASSERT_FALSE(carried.sos.empty());
  EXPECT_NEAR(carried.sos.back().a1, -deep_direct.lowpass_pole, 1e-12);
  EXPECT_NEAR(carried.sos.back().b0, 1.0 - deep_direct.lowpass_pole, 1e-12);
  // In view and far from the cabinet: no loss, no low-pass.
  const HeardReflection clear = translation.reflectionsAt(Eigen::Vector3d(2.0, 4.3, 1.4)).front();
  EXPECT_EQ(clear.lowpass_pole, 0.0);
  EXPECT_NEAR(clear.reflection.level * (Eigen::Vector3d(2.0, 4.3, 1.4) - room.source).norm(), 1.0, 1e-9);
}

TEST(ListenerTranslation, TheDirectSoundFadesSmoothlyIntoAnObjectsShadow) {
  // Walking out of the cabinet's shadow over its top edge in 2 mm steps: no step in the
  // direct sound's level above 0.5 dB, and none in its time above the step's own 6 us.
  const CabinetRoom room = cabinetRoom();
  ListenerTranslationOptions options;
  options.speed_of_sound_m_s = kC;
  const ListenerTranslation translation(room.rsao, room.rig, Eigen::Quaterniond::Identity(), room.model, options);
  double previous_db = 0.0, previous_s = 0.0, worst_db = 0.0, worst_s = 0.0;
  int steps = 0;
  for (double z = 0.8; z <= 2.4; z += 0.002, ++steps) {
    const EarlyReflection r = translation.reflectionsAt(Eigen::Vector3d(5.5, 2.5, z)).front().reflection;
    const double db = 20.0 * std::log10(r.level);
    if (steps > 0) {
      worst_db = std::max(worst_db, std::abs(db - previous_db));
      worst_s = std::max(worst_s, std::abs(r.time_of_arrival_s - previous_s));
    }
    previous_db = db;
    previous_s = r.time_of_arrival_s;
  }
  EXPECT_LT(worst_db, 0.5);
  EXPECT_LT(worst_s, 6e-6);
}

TEST(ListenerTranslation, EveryReflectionKeepsItsPlaceHeardOrNot) {
  // A renderer keeps one tap per reflection: reflectionsAt lists them all, in the anchors'
  // order, and at() is its heard part.
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kHeldOut, 9);
  const ListenerTranslation translation(exactRsao(capture), capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                        modelOf(capture.geometry));
  for (double dy = -2.0; dy <= 2.0; dy += 0.5) {
    const Eigen::Vector3d listener = capture.geometry.receiver_m + Eigen::Vector3d(-0.2, dy, 0.0);
    if ((listener.array() < 0.3).any() || ((capture.geometry.size_m - listener).array() < 0.3).any()) continue;
    const std::vector<HeardReflection> all = translation.reflectionsAt(listener);
    ASSERT_EQ(all.size(), translation.anchors().size());
    std::size_t heard = 0;
    for (const HeardReflection& h : all) {
      heard += h.heard;
      if (!h.heard) {
        EXPECT_EQ(h.reflection.level, 0.0);
      }
    }
    EXPECT_TRUE(all.front().heard);
    EXPECT_EQ(translation.at(listener).reflections.size(), heard);
    // The renderer's moves alone (arrivalsAt) are the same moves.
    std::vector<MovedArrival> arrivals;
    translation.arrivalsAt(listener, arrivals);
    ASSERT_EQ(arrivals.size(), all.size());
    for (std::size_t k = 0; k < all.size(); ++k) {
      EXPECT_EQ(arrivals[k].heard, all[k].heard) << k;
      EXPECT_EQ(arrivals[k].time_of_arrival_s, all[k].reflection.time_of_arrival_s) << k;
      EXPECT_EQ(arrivals[k].level, all[k].reflection.level) << k;
      EXPECT_NEAR(arrivals[k].direction.norm(), 1.0, 1e-12) << k;
      EXPECT_LT(angleDeg(arrivals[k].direction, directionOf(all[k].reflection)), 1e-6) << k;
    }
  }
}

TEST(ListenerTranslation, AnUnmatchedReflectionKeepsItsDirectionAndFades) {
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, 1);
  Rsao rsao = exactRsao(capture, 1);
  // A reflection from nowhere in the room: straight up from below the floor, 7 ms late.
  EarlyReflection stray = rsao.reflections.front();
  stray.time_of_arrival_s += 0.007;
  stray.distance_m += kC * 0.007;
  stray.elevation_rad = -1.2;
  stray.level *= 0.5;
  rsao.reflections.push_back(stray);
  const ListenerTranslation translation(rsao, capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                        modelOf(capture.geometry));
  ASSERT_EQ(translation.anchors()[rsao.reflections.size() - 1].anchor, ReflectionAnchor::kUnmatched);
  // Steps towards the middle of the room.
  Eigen::Vector3d inwards = 0.5 * capture.geometry.size_m - capture.geometry.receiver_m;
  inwards.z() = 0.0;
  inwards.normalize();
  for (const double step : {0.5, 1.0, 2.0}) {
    const Rsao moved = translation.at(capture.geometry.receiver_m + step * inwards);
    const double gain = std::exp(-step * step);
    bool seen = false;
    for (const EarlyReflection& r : moved.reflections) {
      if (std::abs(r.time_of_arrival_s - stray.time_of_arrival_s) > 1e-9) continue;
      seen = true;
      EXPECT_NEAR(r.elevation_rad, -1.2, 1e-12);
      EXPECT_NEAR(r.level, stray.level * gain, 1e-12);
    }
    EXPECT_EQ(seen, gain >= 1e-3) << step;
  }
}

TEST(ListenerTranslation, TheRigsRotationTurnsDirectionsIntoTheRigsAxes) {
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, 2);
  // The same RSAO as a rig turned 90 degrees to the left would measure it.
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitZ()));
  Rsao in_rig = exactRsao(capture);
  for (EarlyReflection& r : in_rig.reflections) {
    const Eigen::Vector3d u = turned.conjugate() * directionOf(r);
    r.azimuth_rad = std::atan2(u.y(), u.x());
    r.elevation_rad = std::asin(std::clamp(u.z(), -1.0, 1.0));
  }
  const ListenerTranslation translation(in_rig, capture.geometry.receiver_m, turned, modelOf(capture.geometry));
  EXPECT_LT((translation.sourcePosition() - capture.geometry.source_m).norm(), 1e-6);
  const Eigen::Vector3d offset = listenerOffsets(capture.geometry, 1, 3).front();
  const Rsao moved = translation.at(capture.geometry.receiver_m + offset);
  const Rsao truth = exactRsao(reflectionRoom(ReflectionRoomSet::kDevelopment, 2, offset));
  ASSERT_EQ(moved.reflections.size(), truth.reflections.size());
  for (std::size_t k = 0; k < truth.reflections.size(); ++k) {
    EXPECT_LT(angleDeg(turned * directionOf(moved.reflections[k]), directionOf(truth.reflections[k])), 0.01) << k;
  }
}

TEST(ListenerTranslation, BadInputIsRefusedInOneLine) {
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, 0);
  const RoomModel model = modelOf(capture.geometry);
  const Eigen::Vector3d rig = capture.geometry.receiver_m;
  const auto refused = [](const auto& make, const std::string& fragment) {
    try {
      make();
      ADD_FAILURE() << "accepted; expected: " << fragment;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  const Eigen::Quaterniond identity = Eigen::Quaterniond::Identity();
  refused([&] { ListenerTranslation(Rsao{}, rig, identity, model); }, "no direct sound");
  Rsao no_distance = exactRsao(capture);
  no_distance.reflections[1].distance_m = 0.0;
  refused([&] { ListenerTranslation(no_distance, rig, identity, model); }, "no image-source distance");
  refused([&] { ListenerTranslation(exactRsao(capture), Eigen::Vector3d(-1.0, 1.0, 1.0), identity, model); },
          "the rig (-1, 1, 1) m is outside the room model's box");
  Rsao far_source = exactRsao(capture);
  far_source.reflections[0].distance_m = 50.0;
  refused([&] { ListenerTranslation(far_source, rig, identity, model); }, "the source");
  ListenerTranslationOptions bad;
  bad.match_angle_deg = 200.0;
  refused([&] { ListenerTranslation(exactRsao(capture), rig, identity, model, bad); }, "match_angle_deg");

  const ListenerTranslation translation(exactRsao(capture), rig, identity, model);
  refused([&] { translation.at(Eigen::Vector3d(NAN, 1.0, 1.0)); }, "not finite");
  refused([&] { translation.at(Eigen::Vector3d(1.0, 1.0, 50.0)); }, "outside the room model's box");
  RoomModel furnished = model;
  CuboidObject table;
  table.label = "table";
  table.material = "wood";
  table.center_m = {1.0, 1.0, 0.4};
  table.size_m = {0.8, 0.8, 0.8};
  furnished.objects.push_back(table);
  const ListenerTranslation in_furnished(exactRsao(capture), rig, identity, furnished);
  refused([&] { in_furnished.at(Eigen::Vector3d(1.0, 1.0, 0.4)); }, "inside object 0 (table)");
}

// Per octave band, the energy the resynthesis of `rsao` is made to hold over samples
// [from, to): its taps as played (their band energy) plus its late envelope's (the
// expected energy of the unit-mean-square noise under it).
std::vector<double> expectedBandEnergies(const Rsao& rsao, std::size_t from, std::size_t to) {
  ResynthesisOptions options;
  options.include_late = false;
  options.duration_s = static_cast<double>(to) / 48000.0 + 0.2;
  std::vector<double> energy;
  const std::vector<float> taps = resynthesizeRsao(rsao, options).channels[0];
  for (const std::vector<float>& band : BandFilterBank(standardBands(BandResolution::kOctave), 48000.0).split(taps)) {
    double e = 0.0;
    for (std::size_t n = from; n < std::min(to, band.size()); ++n) e += static_cast<double>(band[n]) * band[n];
    energy.push_back(e + lateEnvelopeEnergy(rsao.late, energy.size(), from, to, 48000.0));
  }
  return energy;
}

TEST(ListenerTranslation, CompletedReflectionsTakeTheirEnergyFromTheLateCourse) {
  // The late part's early course was fitted to the measured early energy, the missed
  // reflections' included: the completed ones take theirs from it, band by band, so that
  // the translation heard at the capture point holds, from the direct sound to the end of
  // the course, the early energy the measured RSAO holds. Over the late part as measured
  // they would count twice.
  double worst_db = 0.0, worst_doubled_db = 0.0;
  int completed = 0;
  for (std::size_t index : {0u, 4u, 11u}) {
    const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, index);
    const Rsao measured = estimateRsao(capture.ambix, AmbisonicFormat::kAmbiX);
    const ListenerTranslation translation(measured, capture.geometry.receiver_m, Eigen::Quaterniond::Identity(),
                                          modelOf(capture.geometry));
    completed += static_cast<int>(translation.reflectionsAtRig().size() - measured.reflections.size());
    const auto from = static_cast<std::size_t>((measured.reflections.front().time_of_arrival_s - 0.001) * 48000.0);
    const auto to = static_cast<std::size_t>(std::ceil(std::max(measured.late.course_end_s, measured.late.mixing_time_s) * 48000.0));
    const Rsao heard = translation.at(capture.geometry.receiver_m);
    Rsao doubled = heard;
    doubled.late = measured.late;
    const std::vector<double> before = expectedBandEnergies(measured, from, to);
    const std::vector<double> after = expectedBandEnergies(heard, from, to);
    const std::vector<double> twice = expectedBandEnergies(doubled, from, to);
    for (std::size_t b = 1; b + 2 < before.size(); ++b) {  // 125 Hz - 4 kHz
      worst_db = std::max(worst_db, std::abs(10.0 * std::log10(after[b] / before[b])));
      worst_doubled_db = std::max(worst_doubled_db, 10.0 * std::log10(twice[b] / before[b]));
    }
    // Only the onset course changes: the decay after the mixing time is the measured one.
    for (std::size_t b = 0; b < measured.late.bands.size(); ++b) {
      EXPECT_EQ(translation.late().bands[b].level, measured.late.bands[b].level);
      EXPECT_EQ(translation.late().bands[b].decay_constant_per_s, measured.late.bands[b].decay_constant_per_s);
    }
  }
  std::printf("[ measured ] %d completed reflections; early energy 125 Hz-4 kHz at the capture point within %.3f dB of "
              "the measured RSAO's (over the late part as measured: up to %+.2f dB)\n",
              completed, worst_db, worst_doubled_db);
  EXPECT_GT(completed, 5);
  EXPECT_LT(worst_db, 0.01);
  EXPECT_GT(worst_doubled_db, 0.3);
}

TEST(OnsetRampFit, AddedReflectionsYieldTheirBandEnergy) {
  const ReflectionRoom capture = reflectionRoom(ReflectionRoomSet::kDevelopment, 0);
  const Rsao measured = estimateRsao(capture.ambix, AmbisonicFormat::kAmbiX);
  ASSERT_GE(measured.reflections.size(), 3u);
  const auto span = [&](const Rsao& r) {
    const auto from = static_cast<std::size_t>(std::floor((r.reflections.front().time_of_arrival_s - 0.001) * 48000.0));
    const auto to = static_cast<std::size_t>(std::ceil(std::max(r.late.course_end_s, r.late.mixing_time_s) * 48000.0));
    return std::make_pair(from, to);
  };
  const auto [from, to] = span(measured);
  // The band energy added reflections bring, as the resynthesis plays them beside the
  // RSAO's own taps.
  const auto brought = [&, from = from, to = to](const std::vector<EarlyReflection>& added) {
    ResynthesisOptions options;
    options.include_late = false;
    options.duration_s = measured.late.mixing_time_s + 0.2;
    const BandFilterBank bank(standardBands(BandResolution::kOctave), 48000.0);
    const auto energies = [&](const std::vector<EarlyReflection>& extra) {
      Rsao taps = measured;
      taps.reflections.insert(taps.reflections.end(), extra.begin(), extra.end());
      std::vector<double> energy;
      for (const std::vector<float>& band : bank.split(resynthesizeRsao(taps, options).channels[0])) {
        double e = 0.0;
        for (std::size_t n = from; n < std::min(to, band.size()); ++n) e += static_cast<double>(band[n]) * band[n];
        energy.push_back(e);
      }
      return energy;
    };
    std::vector<double> with = energies(added);
    const std::vector<double> own = energies({});
    for (std::size_t b = 0; b < with.size(); ++b) with[b] -= own[b];
    return with;
  };
  EarlyReflection copy = measured.reflections[2];
  copy.time_of_arrival_s = 0.5 * (measured.reflections[2].time_of_arrival_s + measured.late.mixing_time_s);
  for (const double louder : {0.3, 30.0}) {
    std::vector<EarlyReflection> added{copy};
    added[0].level *= louder;
    Rsao yielded = measured;
    const double gain = yieldOnsetEnergy(added, yielded);
    EXPECT_NEAR(added[0].level, gain * copy.level * louder, 1e-12);
    if (louder < 1.0) {
      EXPECT_EQ(gain, 1.0);
    } else {
      EXPECT_LT(gain, 1.0);
    }
    const std::vector<double> now_brought = brought(added);  // at the level it now has
    bool at_floor = false;
    for (std::size_t b = 0; b < measured.late.bands.size(); ++b) {
      if (!(measured.late.bands[b].level > 0.0)) continue;
      const double held = lateEnvelopeEnergy(measured.late, b, from, to, 48000.0);
      const double now = lateEnvelopeEnergy(yielded.late, b, from, to, 48000.0);
      const double floor = measured.late.bands[b].level * std::pow(10.0, -40.0 / 20.0);
      at_floor |= std::abs(yielded.late.bands[b].onset_level / floor - 1.0) < 1e-3;
      // Exactly what the reflection brings, where the course can give it.
      if (yielded.late.bands[b].onset_level > 1.001 * floor && std::abs(now_brought[b]) > 1e-6 * held) {
        EXPECT_NEAR((held - now) / now_brought[b], 1.0, 1e-3) << "band " << b << ", " << louder << " x";
      }
    }
    if (louder > 1.0) {
      EXPECT_TRUE(at_floor) << "the limiting band gives all it holds";
    }
  }
  std::vector<EarlyReflection> none;
  Rsao untouched = measured;
  EXPECT_EQ(yieldOnsetEnergy(none, untouched), 1.0);
  for (std::size_t b = 0; b < measured.late.bands.size(); ++b) {
    EXPECT_EQ(untouched.late.bands[b].onset_level, measured.late.bands[b].onset_level);
  }
}

TEST(ListenerTranslation, EstimatedRsaoMovedOnDevelopmentRooms) {
  // Three development rooms (two shoeboxes, a close pair), two steps each.
  MovedScore total;
  for (std::size_t index : {0u, 4u, 11u}) total.add(scoreMovedRoom(ReflectionRoomSet::kDevelopment, index, 2));
  std::printf("[ measured ] %s\n", describe(total).c_str());
  // What was found at the capture point stays found, timed and pointed at the new
  // position: nearly as much as the estimator finds in that position's own RIR (all of it
  // here; moved 39 of 44), far more than the RSAO left where it was measured, and what it
  // reports is real.
  EXPECT_GE(withinBoth(total.moved), 0.85 * withinBoth(total.own));
  EXPECT_GE(withinBoth(total.moved), 4 * withinBoth(total.still));
  EXPECT_GE(total.withinShare(), 0.9);
  EXPECT_GE(total.moved.precision(), 0.9);
}

// The signed median of one octave's errors (they run band by band, six to an RIR:
// 125 Hz-4 kHz).
double bandMedian(const std::vector<double>& early_db, std::size_t band) {
  std::vector<double> values;
  for (std::size_t i = band; i < early_db.size(); i += 6) values.push_back(early_db[i]);
  return quantileLinear(values, 0.5);
}

TEST(ListenerTranslation, TheDirectSoundKeepsItsLevelWhereAReflectionFollowsItClosely) {
  // The near-direct development rooms: a reflection within the direct sound's 2 ms window.
  // Their DRR at the capture point is within 0.6 dB of the room's (+0.3, +0.2 and +0.5 dB;
  // with the window's whole energy as the direct sound's level +0.6, +0.8 and +0.8 dB).
  int rooms = 0;
  for (std::size_t index = 0; index < reflectionRoomCount(ReflectionRoomSet::kDevelopment); ++index) {
    if (reflectionRoom(ReflectionRoomSet::kDevelopment, index).name.rfind("near-direct", 0) != 0) continue;
    const MovedScore score = scoreMovedRoom(ReflectionRoomSet::kDevelopment, index, 0, true);
    ASSERT_EQ(score.capture_drr_db.size(), 1u);
    EXPECT_LT(std::abs(score.capture_drr_db.front()), 0.6) << index;
    ++rooms;
  }
  EXPECT_EQ(rooms, 3);
}

TEST(ListenerTranslation, MovedLowBandsStayNearTheTruth) {
  // The early energy at the moved positions, 125 and 250 Hz, of the eight development
  // shoeboxes, four steps each: each tap fitted on its arrival alone (early_reflections.h),
  // its spectrum held below the window's resolution (the default) or fitted whole (the
  // paper's). Measured: +0.41 and +0.57 dB, |error| median 0.50 dB over 125 Hz-4 kHz; the
  // paper's fit +0.36, +0.50 and 0.47 dB. Fitted on the RIR's window, whose taps carry their
  // neighbours' low frequencies once each, the paper's fit gives +1.33, +1.51 and 0.72 dB.
  RsaoOptions paper;
  paper.early.lpc_flat_below_hz = 0.0;
  MovedScore held, whole;
  for (std::size_t index = 0; index < 8; ++index) {
    held.add(scoreMovedRoom(ReflectionRoomSet::kDevelopment, index, 4, true));
    whole.add(scoreMovedRoom(ReflectionRoomSet::kDevelopment, index, 4, true, paper));
  }
  std::vector<double> held_abs, whole_abs;
  for (double e : held.moved_early_db) held_abs.push_back(std::abs(e));
  for (double e : whole.moved_early_db) whole_abs.push_back(std::abs(e));
  std::printf("[ measured ] moved early energy: 125 Hz %+.2f dB, 250 Hz %+.2f dB, |error| median %.2f dB (the paper's "
              "fit: %+.2f, %+.2f, %.2f dB)\n",
              bandMedian(held.moved_early_db, 0), bandMedian(held.moved_early_db, 1), quantileLinear(held_abs, 0.5),
              bandMedian(whole.moved_early_db, 0), bandMedian(whole.moved_early_db, 1), quantileLinear(whole_abs, 0.5));
  for (std::size_t band : {0u, 1u}) {
    EXPECT_LT(std::abs(bandMedian(held.moved_early_db, band)), 0.8) << band;
    EXPECT_LT(std::abs(bandMedian(whole.moved_early_db, band)), 0.8) << band;
  }
  EXPECT_LT(quantileLinear(held_abs, 0.5), 0.6);
  EXPECT_LT(quantileLinear(whole_abs, 0.5), 0.6);
}

// The report of docs/six_dof.md over both sets; ROOM_REVERB_PER_ROOM=1 adds each room's
// levels, ROOM_REVERB_PER_POSITION=1 each moved position's; ROOM_REVERB_PAPER_LPC=1 fits
// each tap's shape on its whole window (docs/rsao.md's comparison); ROOM_REVERB_LEVEL_SEEDS=N
// takes each resynthesised RSAO's levels over N seeds;
// ROOM_REVERB_PRINT_DRR_PARTS=1 prints each comparison's direct sound, rest and energy
// after 50 ms apart.
TEST(ListenerTranslationReport, BothSets) {
  if (!std::getenv("ROOM_REVERB_SIX_DOF_REPORT")) GTEST_SKIP() << "set ROOM_REVERB_SIX_DOF_REPORT=1 for the report";
  for (const ReflectionRoomSet set : {ReflectionRoomSet::kDevelopment, ReflectionRoomSet::kHeldOut}) {
    if (set == ReflectionRoomSet::kHeldOut && std::getenv("ROOM_REVERB_DEVELOPMENT_ONLY")) continue;
    MovedScore total;
    for (std::size_t i = 0; i < reflectionRoomCount(set); ++i) {
      RsaoOptions estimation;
      if (std::getenv("ROOM_REVERB_PAPER_LPC")) estimation.early.lpc_flat_below_hz = 0.0;
      const MovedScore room = scoreMovedRoom(set, i, 4, true, estimation);
      if (std::getenv("ROOM_REVERB_PER_ROOM")) {
        std::printf("  %-14s capture early, 125 Hz-4 kHz:", reflectionRoom(set, i).name.c_str());
        for (double e : room.capture_early_db) std::printf(" %+.1f", e);
        std::vector<double> moved_abs;
        for (double e : room.moved_early_db) moved_abs.push_back(std::abs(e));
        std::vector<double> own_abs;
        for (double e : room.versus_own_early_db) own_abs.push_back(std::abs(e));
        std::printf("; moved |error| median %.2f, p90 %.2f dB (against its own RSAO %.2f, %.2f dB); DRR capture %+.1f, "
                    "moved median %+.1f dB\n",
                    quantileLinear(moved_abs, 0.5), quantileLinear(moved_abs, 0.9), quantileLinear(own_abs, 0.5),
                    quantileLinear(own_abs, 0.9), room.capture_drr_db.front(), quantileLinear(room.moved_drr_db, 0.5));
        if (std::getenv("ROOM_REVERB_PER_POSITION")) {
          for (std::size_t p = 0; p < room.moved_drr_db.size(); ++p) {
            std::printf("      moved to position %zu:", p + 1);
            for (std::size_t b = 0; b < 6; ++b) std::printf(" %+.1f", room.moved_early_db[6 * p + b]);
            std::printf("; DRR %+.1f dB; against its own RSAO:", room.moved_drr_db[p]);
            for (std::size_t b = 0; b < 6; ++b) std::printf(" %+.1f", room.versus_own_early_db[6 * p + b]);
            std::printf("; DRR %+.1f dB\n", room.versus_own_drr_db[p]);
          }
        }
      }
      total.add(room);
    }
    std::printf("%s rooms, 4 listener positions 0.5-2 m from the capture point each:\n%s\n",
                set == ReflectionRoomSet::kDevelopment ? "development" : "held-out", describe(total).c_str());
  }
}

}  // namespace
