#pragma once
// The five measured pairs of the sample room that the diagnosis benchmarks use: two
// loudspeaker positions, five microphone positions, all clear of the furniture
// (data/sample_room/visible.yaml and acoustic.yaml).
#include <string>
#include <utility>
#include <vector>

#include "room_reverb/evaluation/measurements.h"

namespace room_reverb::bench {

inline std::vector<core::MeasurementPair> sampleRoomFivePairs() {
  const Eigen::Vector3d s1(4.6, 2.9, 1.5), s2(1.5, 0.9, 1.6);
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> positions{
      {s1, {2.7, 2.1, 1.4}}, {s1, {1.6, 3.4, 1.3}}, {s2, {3.6, 2.2, 1.2}}, {s2, {4.8, 1.6, 1.4}}, {s1, {3.0, 0.9, 1.2}}};
  std::vector<core::MeasurementPair> pairs;
  for (const auto& [source, receiver] : positions) {
    core::MeasurementPair p;
    p.source_m = source;
    p.receiver_m = receiver;
    p.format = "ambix";
    p.label = "pair" + std::to_string(pairs.size() + 1);
    pairs.push_back(p);
  }
  return pairs;
}

}  // namespace room_reverb::bench
