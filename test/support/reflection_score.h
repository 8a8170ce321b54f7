#pragma once
// Scores an early-reflection estimate against a synthetic room's image sources
// (reflection_rooms.h).
//
// Resolvable reflections (those any estimator should find): first and second order,
// within 30 ms of the direct sound, at most 14 dB below it (level: sqrt of W energy), and
// no comparable arrival (any image source up to third order, the direct sound included,
// at most 6 dB weaker) within 0.3 ms. Found: matched one to one, nearest first, to a
// reported reflection within 0.5 ms. Real: a reported reflection within 30 ms of the
// direct sound that lies within 0.5 ms of some image source of order 1 to 3.
#include <string>
#include <vector>

#include "reflection_rooms.h"
#include "room_reverb/rsao/rsao.h"

namespace room_reverb::test {

struct ReflectionMiss {
  std::string room;
  double delay_ms = 0.0;      // after the direct sound
  double level_db = 0.0;      // re the direct sound
  int order = 0;
  double neighbour_ms = 0.0;  // to the nearest other image source at most 6 dB weaker
  double nearest_report_ms = 0.0;  // signed: nearest reported reflection minus the truth
};

struct ReflectionScore {
  int resolvable = 0;
  int found = 0;
  int reported = 0;  // reflections reported within 30 ms of the direct sound (direct excluded)
  int real = 0;
  std::vector<double> toa_error_ms;    // of the found ones
  std::vector<double> direction_error_deg;
  // Of the found ones, in the same order: the reported image source's distance from the
  // true one [m] (the rooms' c, 343 m/s, from the direct sound's true distance), and the
  // reported confidence (-1 where none).
  std::vector<double> image_source_error_m;
  std::vector<double> found_confidence;
  std::vector<ReflectionMiss> misses;

  void add(const ReflectionScore& other);
  double recall() const { return resolvable > 0 ? static_cast<double>(found) / resolvable : 1.0; }
  double precision() const { return reported > 0 ? static_cast<double>(real) / reported : 1.0; }
  double toaP95Ms() const;
  double directionP95Deg() const;
  std::string summary() const;  // one line
};

// `estimate`: [0] the direct sound, then the reflections (EarlyReflection as the RSAO has it).
ReflectionScore scoreReflections(const ReflectionRoom& room, const std::vector<core::EarlyReflection>& estimate);

}  // namespace room_reverb::test
