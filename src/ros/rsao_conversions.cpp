#include "room_reverb/ros/rsao_conversions.h"

#include <array>
#include <string>

#include "room_reverb/common/error.h"

namespace room_reverb::ros_bridge {

room_reverb::Rsao toMessage(const core::Rsao& rsao) {
  room_reverb::Rsao msg;
  msg.sample_rate_hz = rsao.sample_rate_hz;
  msg.duration_s = rsao.duration_s;
  for (const core::EarlyReflection& r : rsao.reflections) {
    room_reverb::EarlyReflection m;
    m.time_of_arrival_s = r.time_of_arrival_s;
    m.level = r.level;
    m.azimuth_rad = r.azimuth_rad;
    m.elevation_rad = r.elevation_rad;
    m.distance_m = r.distance_m;
    const std::array<double, 3> image = core::imageSourcePosition(r);
    m.image_source.x = image[0];
    m.image_source.y = image[1];
    m.image_source.z = image[2];
    m.confidence = r.confidence.value_or(-1.0);
    m.lpc = r.lpc;
    m.lpc_gain = r.lpc_gain;
    for (const core::BiquadSection& s : r.sos) m.sos.insert(m.sos.end(), {s.b0, s.b1, s.b2, s.a1, s.a2});
    msg.reflections.push_back(m);
  }
  const core::LateReverb& late = rsao.late;
  msg.late.mixing_time_s = late.mixing_time_s;
  msg.late.onset_s = late.onset_s;
  msg.late.attack_time_s = late.attack_time_s;
  msg.late.course_end_s = late.course_end_s;
  for (const core::LateReverbBand& b : late.bands) {
    msg.late.center_hz.push_back(b.center_hz);
    msg.late.decay_constant_per_s.push_back(b.decay_constant_per_s);
    msg.late.t60_s.push_back(b.t60_s);
    msg.late.level.push_back(b.level);
    msg.late.onset_level.push_back(b.onset_level);
    msg.late.first_decay_constant_per_s.push_back(b.first_decay_constant_per_s);
    msg.late.second_decay_constant_per_s.push_back(b.second_decay_constant_per_s);
    msg.late.second_share.push_back(b.second_share);
    msg.late.reliable.push_back(b.reliable);
    msg.late.reason.push_back(b.reason);
  }
  msg.warnings = rsao.warnings;
  return msg;
}

core::Rsao fromMessage(const room_reverb::Rsao& msg) {
  core::Rsao rsao;
  rsao.sample_rate_hz = msg.sample_rate_hz;
  rsao.duration_s = msg.duration_s;
  if (msg.reflections.empty()) throw core::InputError("Rsao message: no reflections; reflections[0] must be the direct sound");
  for (std::size_t k = 0; k < msg.reflections.size(); ++k) {
    const room_reverb::EarlyReflection& m = msg.reflections[k];
    if (m.sos.size() % 5 != 0) {
      throw core::InputError("Rsao message: reflections[" + std::to_string(k) + "].sos has " +
                             std::to_string(m.sos.size()) + " numbers; it needs five (b0 b1 b2 a1 a2) per section");
    }
    core::EarlyReflection r;
    r.time_of_arrival_s = m.time_of_arrival_s;
    r.level = m.level;
    r.azimuth_rad = m.azimuth_rad;
    r.elevation_rad = m.elevation_rad;
    r.distance_m = m.distance_m;
    // The image source follows from distance and direction; a confidence outside 0..1
    // (-1) means none was estimated.
    if (m.confidence >= 0.0 && m.confidence <= 1.0) r.confidence = m.confidence;
    r.lpc = m.lpc;
    r.lpc_gain = m.lpc_gain;
    for (std::size_t i = 0; i < m.sos.size(); i += 5) {
      r.sos.push_back({m.sos[i], m.sos[i + 1], m.sos[i + 2], m.sos[i + 3], m.sos[i + 4]});
    }
    rsao.reflections.push_back(r);
  }
  const room_reverb::LateReverb& late = msg.late;
  const std::size_t bands = late.center_hz.size();
  for (std::size_t size : {late.decay_constant_per_s.size(), late.t60_s.size(), late.level.size(),
                           late.onset_level.size(), late.reliable.size(), late.reason.size()}) {
    if (size != bands) {
      throw core::InputError("Rsao message: the late band arrays differ in length (center_hz has " +
                             std::to_string(bands) + ", another " + std::to_string(size) + ")");
    }
  }
  const bool two_slopes = !late.second_share.empty();
  for (std::size_t size : {late.first_decay_constant_per_s.size(), late.second_decay_constant_per_s.size(),
                           late.second_share.size()}) {
    if (size != (two_slopes ? bands : 0)) {
      throw core::InputError("Rsao message: the two-slope arrays (first_decay_constant_per_s, "
                             "second_decay_constant_per_s, second_share) need one entry per band, or none");
    }
  }
  rsao.late.mixing_time_s = late.mixing_time_s;
  rsao.late.onset_s = late.onset_s;
  rsao.late.attack_time_s = late.attack_time_s;
  rsao.late.course_end_s = late.course_end_s;
  for (std::size_t b = 0; b < bands; ++b) {
    core::LateReverbBand band;
    band.center_hz = late.center_hz[b];
    band.decay_constant_per_s = late.decay_constant_per_s[b];
    band.t60_s = late.t60_s[b];
    band.level = late.level[b];
    band.onset_level = late.onset_level[b];
    if (two_slopes) {
      band.first_decay_constant_per_s = late.first_decay_constant_per_s[b];
      band.second_decay_constant_per_s = late.second_decay_constant_per_s[b];
      band.second_share = late.second_share[b];
    }
    band.reliable = late.reliable[b];
    band.reason = late.reason[b];
    rsao.late.bands.push_back(band);
  }
  rsao.warnings = msg.warnings;
  return rsao;
}

}  // namespace room_reverb::ros_bridge
