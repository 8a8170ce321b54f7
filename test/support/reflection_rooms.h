#pragma once
// Synthetic first-order B-format rooms whose early reflections are known exactly, for
// scoring an early-reflection estimator on what a listener hears: how many of the
// resolvable reflections it finds, how well it times and points them, and whether what it
// reports is real (reflection_score.h).
//
// A room: a shoebox (optionally with a free-hanging reflector panel), exact image sources
// up to third order with their true directions, each rendered as a band-limited pulse
// (low-passed once per bounce where the walls are dull), plus a diffuse tail standing for
// everything of higher order and a white noise floor. Two sets: DEVELOPMENT (what an
// estimator may be tuned on) and HELD-OUT (other seeds, other room shapes and
// absorptions, a reflector panel), which nothing is tuned on.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::test {

enum class ReflectionRoomSet { kDevelopment, kHeldOut };

struct ImageArrival {
  int order = 0;           // 0: the direct sound
  double time_s = 0.0;     // geometric delay: path length / c, from the first sample
  double level = 0.0;      // sqrt of the rendered pulse's energy in W
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit, towards where it comes from
};

struct ReflectionRoom {
  std::string name;                  // kind and seed, e.g. "dull 3"
  core::AudioBuffer ambix;           // first-order AmbiX (SN3D), 48 kHz
  std::vector<ImageArrival> images;  // every rendered image source, orders 0..3, by time
};

std::size_t reflectionRoomCount(ReflectionRoomSet set);

// The index-th room of a set (deterministic); an index past the count
// throws std::out_of_range.
ReflectionRoom reflectionRoom(ReflectionRoomSet set, std::size_t index);

}  // namespace room_reverb::test
