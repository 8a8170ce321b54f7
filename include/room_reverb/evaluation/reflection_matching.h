#pragma once
// Early reflections of a measured RIR set against those of its simulation: both RSAOs'
// reflections are placed relative to their own direct sound (time after it, level in dB
// re it, direction of arrival) and paired by time, so a constant offset between the two
// recordings (latency, a source moved along the direct path) does not break the match.
#include <vector>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

struct ReflectionMatchOptions {
  // Two reflections can pair when their delays after the direct sound differ by at most
  // this: 1 ms is 34 cm of path, more than a visual room model's wall errors (about 10 cm,
  // twice over for a first-order path) and less than the spacing of most first-order
  // reflections in a furnished room.
  double time_tolerance_s = 0.001;
};

// A reflection relative to its RSAO's direct sound.
struct RelativeReflection {
  int index = 0;              // in the RSAO's reflections (>= 1)
  double delay_s = 0.0;       // after the direct sound
  double level_db = 0.0;      // 20 log10 of level / direct level
  double azimuth_deg = 0.0;   // DESIGN.md: counter-clockwise from +x
  double elevation_deg = 0.0;
};

// An RSAO's reflections (not the direct sound) relative to its direct sound; empty without
// a direct sound of positive level.
std::vector<RelativeReflection> relativeReflections(const Rsao& rsao);

struct MatchedReflection {
  RelativeReflection measured, simulated;
  double time_error_ms = 0.0;        // simulated - measured delay
  double direction_error_deg = 0.0;  // great-circle angle between the two directions
  double level_error_db = 0.0;       // simulated - measured
};

struct ReflectionMatching {
  std::vector<MatchedReflection> matched;            // by measured delay
  std::vector<RelativeReflection> measured_only;     // no simulated counterpart
  std::vector<RelativeReflection> simulated_only;    // no measured counterpart
};

// Pairs the reflections (not the direct sounds) of two RSAOs: candidate pairs within the
// time tolerance are taken in order of increasing time difference, each reflection used
// once. RSAOs without a direct sound give everything unmatched.
ReflectionMatching matchReflections(const Rsao& measured, const Rsao& simulated,
                                    const ReflectionMatchOptions& options = {});

}  // namespace room_reverb::core
