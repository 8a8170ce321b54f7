#pragma once
// The RSAO as a YAML file (rsao.yaml), the project's own lossless form of an Rsao: what
// `room_reverb rsao` writes and the renderer and evaluation tools read.
//
//   format: room_reverb_rsao
//   version: 1
//   sample_rate_hz: 48000
//   duration_s: 1.5
//   reflections:                  # [0] is the direct sound, then by time of arrival
//     - time_of_arrival_s: 0.0042   # from the first sample of the RIR
//       level: 0.31                 # sqrt of the W energy over the analysis window
//       azimuth_deg: 12.5           # counter-clockwise from +x
//       elevation_deg: -3           # up from the horizontal plane
//       distance_m: 1.44
//       lpc: [1, -1.2, 0.5]         # A(z); the reflection's shape is lpc_gain / A(z)
//       lpc_gain: 0.8
//       sos:                        # the same filter as second-order sections, a0 = 1
//         - {b0: 0.8, b1: 0, b2: 0, a1: -1.2, a2: 0.5}
//   late:
//     mixing_time_s: 0.061
//     onset_s: 0.0083
//     attack_time_s: 0.0527
//     course_end_s: 0.111           # where the bands' extended early course ends (late_envelope.h)
//     bands:                        # none, or the nine octaves 63 Hz .. 16 kHz
//       - {center_hz: 62.5, decay_constant_per_s: 3.84, t60_s: 1.8, level: 0.02, onset_level: 0.05,
//          reliable: true, reason: ""}  # onset_level: late_envelope.h
//       - {center_hz: 125, decay_constant_per_s: 5.1, t60_s: 1.35, level: 0.03, onset_level: 0.07,
//          first_decay_constant_per_s: 9.5, second_decay_constant_per_s: 3.8, second_share: 0.07,
//          reliable: true, reason: ""}  # a bent decay (rsao.h); written only where second_share > 0
//   warnings: ["..."]
//
// Radians in code, degrees in the file (the keys say so). Numbers are written as the
// shortest decimals that read back exactly (the same goal as max_digits10, but readable),
// and degrees are chosen so that write -> read -> write gives identical text. Strings are
// double-quoted. Keys may be added; these may not be renamed.
//
// Reading throws InputError naming the key (and line) at fault: a missing required key, a
// value that is not a number, a band list that is not empty or nine long, an lpc whose first
// coefficient is not 1, or a decay constant and T60 that disagree. Optional: sample_rate_hz
// (48000), duration_s (0), distance_m (0), lpc ([]), lpc_gain (1), sos ([]), warnings ([]),
// a band's onset_level (0: the paper's linear ramp from zero), late.course_end_s (0),
// a band's second_share (0: one slope; otherwise both two-slope decay constants are required);
// a band needs one of decay_constant_per_s and t60_s, reliable defaults to true.
#include <string>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

std::string rsaoToYaml(const Rsao& rsao);
Rsao parseRsaoYaml(const std::string& yaml_text, const std::string& source = "rsao");
void saveRsaoYaml(const std::string& path, const Rsao& rsao);
Rsao loadRsaoYaml(const std::string& path);

}  // namespace room_reverb::core
