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
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::test {

enum class ReflectionRoomSet { kDevelopment, kHeldOut };

struct ImageArrival {
  int order = 0;           // 0: the direct sound
  double time_s = 0.0;     // geometric delay: path length / c, from the first sample
  double level = 0.0;      // sqrt of the rendered pulse's energy in W
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit, towards where it comes from
};

// A free-hanging reflector panel parallel to the x walls at x = x_m, spanning
// [y0, y1] x [z0, z1], lit from the -x side.
struct ReflectorPanel {
  double x_m = 0.0, y0 = 0.0, y1 = 0.0, z0 = 0.0, z1 = 0.0;
};

struct ReflectionRoomGeometry {
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();  // the shoebox [0, size]
  Eigen::Vector3d source_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d receiver_m = Eigen::Vector3d::Zero();
  std::optional<ReflectorPanel> panel;
};

struct ReflectionRoom {
  std::string name;                  // kind and seed, e.g. "dull 3"
  core::AudioBuffer ambix;           // first-order AmbiX (SN3D), 48 kHz
  // The same response without the measurement's noise floor: the room's own levels, which
  // an estimate is scored against (at 45 dB SNR the noise holds as much energy after
  // 0.2 s as the tail).
  core::AudioBuffer noiseless;
  std::vector<ImageArrival> images;  // every rendered image source, orders 0..3, by time
  ReflectionRoomGeometry geometry;
};

// The pulse of one arrival in W as the rooms render it, starting at sample `first`: a
// 20 kHz band-limited impulse at the fractional sample `delay_samples` under a Blackman
// window, then `bounces` one-pole low-passes at cutoff_hz (dull walls; 0: none).
struct ArrivalPulse {
  long first = 0;
  std::vector<double> samples;
};
ArrivalPulse renderArrivalPulse(double delay_samples, double amplitude, int bounces, double cutoff_hz);

// The room model of a room's geometry: its box (every surface "plaster_smooth") with the panel as
// a 2 cm cuboid whose lit face is the panel's plane, the rig at the receiver.
core::RoomModel roomModelOf(const ReflectionRoomGeometry& geometry);

std::size_t reflectionRoomCount(ReflectionRoomSet set);

// The index-th room of a set (deterministic); an index past the count
// throws std::out_of_range.
ReflectionRoom reflectionRoom(ReflectionRoomSet set, std::size_t index);

// The same room (walls, source, diffuse tail and noise drawn alike) heard with the
// receiver moved by `receiver_offset_m` (room frame). The tail stands for the room's
// diffuse field, which is alike everywhere in it. Throws std::invalid_argument where the
// moved receiver is within 0.3 m of a wall or 0.5 m of the source, or not on the source's
// side of the panel.
ReflectionRoom reflectionRoom(ReflectionRoomSet set, std::size_t index, const Eigen::Vector3d& receiver_offset_m);

}  // namespace room_reverb::test
