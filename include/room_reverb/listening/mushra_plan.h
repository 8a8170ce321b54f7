#pragma once
// The plan of a MUSHRA listening test (`room_reverb mushra make --plan PLAN.yaml`): which
// rooms, which dry contents, which attributes to ask about, which renders (conditions) to
// compare on every page, which of them are hidden anchors and which are also shown as
// labelled references, and the seed that fixes every random choice.
//
//   seed: 7                          # required; letters, RSAO late noise, ray tracing
//   scale: 0-5                       # 0-5 (default: integers, as Remaggi et al.) or 0-100
//   duration_s: 6.0                  # optional cut length; default: the content's shortest stimulus
//   loudness_lufs: -23               # optional target of the loudness matching (default -23)
//   hrtf: my_head.sofa               # optional; default: the bundled KU100 set
//   decoder: magls                   # optional ambisonic decoder (as `render --decoder`)
//   simulation: {rays: 100000, image_source_order: 3, ambisonic_order: 1, duration_s: 2.0, threads: 0}
//   rooms:
//     - name: studio                 # letters, digits, '_', '-', '.'; names folders of DIR
//       bformat_rir: studio_rir.wav  # measured first-order B-format RIR...
//       format: ambix                # ...and its convention: fuma | ambix
//       room: studio_room.yaml       # room model (room.yaml) for fast / accurate...
//       source_m: [4.6, 2.9, 1.5]    # ...with the source and listener in its room frame
//       listener_m: [2.7, 2.1, 1.4]
//       panorama: studio.jpg         # optional; shown with the spatial attribute
//       wrong_room_of: church        # optional; whose reference RIR is this room's wrong_room
//   contents:
//     - {name: speech, file: speech.wav}
//   attributes:
//     - {id: spatial_impression, question: "How well does the sound match the room you see?"}
//     - {id: overall_quality, question: "How good is the overall sound quality?"}
//   conditions: [reference, rsao, fast, accurate, wrong_room, lowpass_3k5]
//   hidden_anchors: [reference, wrong_room, lowpass_3k5]   # default: those of these three present
//   shown_references: [reference]                          # default: none
//
// Conditions: reference (the measured B-format RIR, binaurally), rsao (the RSAO estimated
// from that RIR), fast and accurate (the room model simulated in either mode), wrong_room
// (the reference RIR of another room of the plan: the next room in the list that has one,
// or `wrong_room_of`), lowpass_3k5 (the reference low-passed at 3.5 kHz, the ITU-R
// BS.1534-3 low anchor). Relative paths are relative to the plan's folder; every file is
// checked when the plan is read.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/listening/mushra_results.h"

namespace room_reverb::core {

// Every condition a plan may name, in a fixed order (for messages).
const std::vector<std::string>& mushraConditionNames();

struct MushraRoom {
  std::string name;
  std::string bformat_rir;                  // path, or "" when the room has no measured RIR
  AmbisonicFormat format = AmbisonicFormat::kAmbiX;  // of bformat_rir
  std::string room_model;                   // path of a room.yaml, or ""
  std::optional<Eigen::Vector3d> source_m;  // room frame; with room_model
  std::optional<Eigen::Vector3d> listener_m;
  std::string panorama;                     // path, or ""
  // The room whose reference RIR this room's wrong_room condition plays; resolved when
  // the plan uses wrong_room, else "".
  std::string wrong_room_of;
};

struct MushraContent {
  std::string name;
  std::string file;  // the dry (anechoic) recording
};

struct MushraAttribute {
  std::string id;        // e.g. spatial_impression
  std::string question;  // what the page asks
  // Whether the page shows the room's panorama: `show_panorama` in the plan, by default
  // true for spatial_impression (the paper rates it against the room's picture) only.
  bool show_panorama = false;
};

// The simulations behind fast and accurate (room_simulation.h); the seed is the plan's.
struct MushraSimulation {
  int image_source_order = 3;
  int rays = 100000;  // accurate mode
  int ambisonic_order = 1;
  double duration_s = 2.0;
  int threads = 0;  // 0: all cores; each ray's path depends on the seed only, the last bits
                    // of the summed energies on the thread count
};

struct MushraPlan {
  std::string source;  // the plan file, for messages
  std::uint32_t seed = 0;
  MushraScale scale = MushraScale::kZeroToFive;
  std::optional<double> duration_s;  // empty: each content's shortest stimulus
  double loudness_lufs = -23.0;
  double max_peak_dbfs = -1.0;  // no sample of any stimulus above this
  std::string hrtf;             // SOFA file
  DecoderMethod decoder = DecoderMethod::kMagLs;
  MushraSimulation simulation;
  std::vector<MushraRoom> rooms;
  std::vector<MushraContent> contents;
  std::vector<MushraAttribute> attributes;
  std::vector<std::string> conditions;  // in the plan's order
  std::vector<std::string> hidden_anchors;
  std::vector<std::string> shown_references;

  bool uses(const std::string& condition) const;
  const MushraRoom& room(const std::string& name) const;  // InputError for an unknown name
};

// Reads and checks a plan. InputError, naming the plan file, line and key, for: malformed
// YAML; a missing or empty list (rooms, contents, attributes, conditions); an unknown
// condition, scale, format or decoder; duplicate or unusable names; a room that lacks what
// a condition needs (bformat_rir and format for reference, rsao, lowpass_3k5; room,
// source_m and listener_m for fast and accurate); wrong_room in a plan of one room or
// wrong_room_of naming an unknown room, the room itself or a room without a RIR; anchors
// or shown references that are not conditions of the plan; a page that shows the panorama
// of a room that has none; a missing file.
MushraPlan loadMushraPlan(const std::string& path);
// The same on text; relative paths resolve against `base_directory`.
MushraPlan parseMushraPlan(const std::string& yaml_text, const std::string& base_directory,
                           const std::string& source);

// The plan as it was used, every default filled in and every path absolute, in the plan
// format (DIR/plan_used.yaml): reading it again gives the same test.
std::string mushraPlanToYaml(const MushraPlan& plan);

}  // namespace room_reverb::core
