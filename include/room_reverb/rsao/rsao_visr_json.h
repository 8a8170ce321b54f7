#pragma once
// Export and import of an RSAO as S3A/VISR object metadata: a "pointreverb" object
// (objectmodel::PointSourceWithReverb) of the VISR renderer's JSON scene format.
//
//   {"objects": [{
//     "type": "pointreverb", "id": 0, "channels": 0, "group": 0, "priority": 0, "level": 0.31,
//     "position": {"az": 12.5, "el": -3.0, "radius": 1.44},        // the direct sound, degrees
//     "biquadsos": [{"b0": .., "b1": .., "b2": .., "a0": 1.0, "a1": .., "a2": ..}],
//     "room": {
//       "ereflect": [{"delay": 0.0071, "level": 0.48,               // re the direct sound
//                     "position": {"az": 60.0, "el": -20.0, "refdist": 3.9},
//                     "biquadsos": [{"b0": .., "b1": .., "b2": .., "a0": 1.0, "a1": .., "a2": ..}]}],
//       "lreverb": {"delay": 0.0041,                                  // ramp start re the direct sound
//                   "level": "0.065, 0.097, ...",                     // nine bands, linear, re the direct sound
//                   "attacktime": "0.0527, 0.0527, ...",              // ramp length, s
//                   "decayconst": "-3.84, -4.32, ..."}},              // 1/s, amplitude exp(decayconst t)
//     "room_reverb": {"band_reliable": [true, ...], "band_reason": ["", ...],
//                     "band_onset_level": [0.0, 0.12, ...],                   // re the direct sound
//                     "course_end": 0.107,                                    // s, re the direct sound
//                     "band_two_slopes": [[9.5, 3.8, 0.07], ...]}}]}          // bent decays only (rsao.h):
//                                                                             // [first, second decay constant, second share]
//
// What was confirmed from VISR's sources (s3a-spatialaudio/VISR: libobjectmodel's
// point_source_with_reverb_parser.cpp, point_source_parser.cpp, object_parser.cpp,
// librbbl's biquad_coefficient.cpp, libreverbobject's late_reverb_filter_calculator.cpp and
// reverb_parameter_calculator.cpp, the test data point_source_with_reverb_1.json):
//   - the keys: type "pointreverb"; id, channels, group, priority, level; position with az,
//     el (degrees) and radius, or x, y, z; room.ereflect[] with delay, level, position,
//     biquadsos; room.lreverb with delay, level, attacktime, decayconst;
//   - biquads as objects with b0, b1, b2, a1, a2 and an optional a0 that divides the rest;
//     at most 10 sections per reflection (cNumDiscreteReflectionBiquads);
//   - the nine late values of a key are one string of comma-separated numbers (the parser
//     reads the key as a string and splits it; a JSON array would not parse);
//   - late levels are linear in the current parser (an older one read them in dB);
//   - the late envelope: zero until lreverb.delay, a linear ramp to `level` over
//     `attacktime`, then level * exp(decayconst * t) with decayconst in 1/s, negative;
//   - reflection gains and late gains are multiplied by the object's level and reflection
//     delays are applied to the object's signal, so levels and delays are relative to the
//     direct sound (the object itself);
//   - the S3A test data writes "refdist" in a reflection's position (VISR's position parser
//     reads az, el, radius and ignores it).
// What was chosen here:
//   - scalars are written as JSON numbers (VISR's property-tree reader takes numbers and
//     numeric strings alike; the import accepts both, and arrays as well as strings for the
//     band lists);
//   - the object-level "biquadsos" carries the direct sound's filter, as in the S3A test
//     data, though VISR's renderer does not apply it yet;
//   - "room_reverb" is this project's addition (VISR ignores unknown keys): the per-band
//     reliability the estimator found, and the onset levels of this project's extended
//     early course (late_envelope.h). VISR plays its linear ramp instead;
//   - levels: the object's level defaults to the direct sound's level, reflection and late
//     levels are divided by it. The late level is this project's (late_reverb.h: the RMS of
//     the band at the mixing time); VISR multiplies its own band noise (uniform +-1 noise
//     through a band-pass biquad, RMS well under 1) by it, so VISR's tail comes out quieter
//     than resynthesizeRsao's by a band-dependent factor VISR does not document.
// Not carried (the file describes the room relative to the direct sound): the direct
// sound's absolute arrival time and level, LPC coefficients, the RIR's duration and sample
// rate, warnings. An import therefore puts the direct sound at time 0 with level 1 and
// returns the object's level beside the Rsao. With that, export -> import -> export gives
// identical text.
#include <optional>
#include <string>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

struct VisrObjectFields {
  int id = 0;
  int channel = 0;  // "channels": the renderer's input channel carrying the source signal
  int group = 0;
  int priority = 0;
  std::optional<double> level;  // unset on export: the direct sound's level
};

// The scene {"objects": [object]}; `indent` as nlohmann::json::dump (-1: one line). Throws
// InputError for an Rsao VISR cannot hold: no direct sound or a direct-sound level <= 0,
// late bands that are not nine, a non-positive decay constant, more than 10 sections in a
// reflection's filter, a non-finite number.
std::string rsaoToVisrJson(const Rsao& rsao, const VisrObjectFields& fields = {}, int indent = 2);

struct VisrImport {
  Rsao rsao;                // direct sound at t = 0 with level 1, the rest relative to it
  VisrObjectFields fields;  // level always set
};

// Reads a scene (the first "pointreverb" object of "objects", or the one with `object_id`
// when that is >= 0) or a bare object. Throws InputError naming the key at fault: a missing
// key, a band list that is not nine long, a value that is not a number.
VisrImport visrJsonToRsao(const std::string& json_text, int object_id = -1);

}  // namespace room_reverb::core
