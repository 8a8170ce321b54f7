// room_reverb rsao: a measured B-format RIR parameterised into a reverberant spatial audio
// object (the twin of the rsao_estimator node's ~estimate service).
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>

#include "arguments.h"
#include "command.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/rsao/late_envelope.h"
#include "room_reverb/rsao/listener_translation.h"
#include "room_reverb/rsao/rsao_estimator.h"
#include "room_reverb/rsao/rsao_resynthesis.h"
#include "room_reverb/rsao/rsao_visr_json.h"
#include "room_reverb/rsao/rsao_yaml.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb rsao RIR.wav --format fuma|ambix [--yaml OUT.yaml] [--visr-json OUT.json]
                        [--resynthesis OUT.wav] [--max-reflections N] [--window-ms D]
                        [--lpc-order P] [--mixing-time S] [--grid] [--paper-ramp]
                        [--one-slope] [--paper-onsets] [--paper-lpc] [--source-distance M]
                        [--move-to X Y Z [--room ROOM.yaml] [--rig X Y Z]]

Parameterises a measured first-order B-format room impulse response into a reverberant
spatial audio object (RSAO, Remaggi et al.): the direct sound and early reflections (time
of arrival, level, direction, LPC filter) and the late reverb per octave band 63 Hz-16 kHz
(mixing time, decay constant, T60, level, onset ramp, a second slope where the decay
bends, reliability).

  --format F          fuma or ambix: the convention of the file (required; a file whose
                      channel energies contradict it gets a warning, never a silent guess)
  --yaml FILE         write the RSAO in the project's YAML format
  --visr-json FILE    write it as an S3A/VISR "pointreverb" object
  --resynthesis FILE  write the B-format (AmbiX) RIR resynthesised from the parameters
  --max-reflections N early reflections kept, strongest first (default 40)
  --window-ms D       analysis window D around each arrival, ms (default 2)
  --lpc-order P       order of each reflection's LPC filter (default 9)
  --paper-lpc         fit each LPC filter to the window's whole spectrum as the paper does
                      (default: the spectrum below 1/D, which the window cannot resolve, held
                      at its value there; docs/rsao.md)
  --mixing-time S     fixed mixing time, s from the first sample (default: echo density)
  --paper-onsets      early reflections by the paper's group-delay onsets of W, directions
                      from the steered cardioid over the window (default: matching pursuit
                      against copies of the direct sound over all four channels, each
                      arrival taken out before the next is sought; docs/rsao.md)
  --grid              with --paper-onsets: directions by the paper's grid search instead
                      of the closed form
  --source-distance M the loudspeaker's distance from the microphone, m: places each
                      reflection's image source at M plus c times its delay after the
                      direct sound (default: c times the direct sound's time, which takes
                      the file to start at the emission)
  --paper-ramp        keep the paper's linear onset ramp in every band instead of fitting
                      each band's early course to the measured early energy (docs/rsao.md)
  --one-slope         keep the paper's one exponential decay in every late band instead of
                      giving bands whose decay is bent (EDT < T20 < T30) a second, slower
                      slope (docs/rsao.md)
  --move-to X Y Z     the RSAO as heard at this listener position (m, room frame) instead
                      of at the microphone: the source and every reflection's image source
                      stay where they are, the listener moves (docs/six_dof.md)
  --room ROOM.yaml    with --move-to: the room model; reflections are matched to its planes,
                      heard only where their reflection points lie on them, and missing
                      second-order ones are added from the measured walls
  --rig X Y Z         with --move-to: the microphone's position in the room frame, its axes
                      the room's (default: the room model's rig pose)

Prints a summary table. Files at other rates than 48 kHz are resampled to 48 kHz.
Exit status: 0 on success (warnings on stderr), 2 with one line on stderr for bad input.
)";

double degrees(double rad) { return rad * 180.0 / 3.14159265358979323846; }

double decibels(double ratio) { return ratio > 0.0 ? 20.0 * std::log10(ratio) : -300.0; }

void printSummary(const Rsao& rsao, std::ostream& out) {
  out << std::fixed;
  out << "direct sound and " << rsao.reflections.size() - 1 << " early reflections; mixing time "
      << std::setprecision(4) << rsao.late.mixing_time_s << " s\n";
  out << "   #   toa_s    level_db  azimuth_deg  elevation_deg  distance_m  confidence\n";
  const double direct = rsao.reflections.front().level;
  for (std::size_t k = 0; k < rsao.reflections.size(); ++k) {
    const EarlyReflection& r = rsao.reflections[k];
    out << std::setw(4) << k << "  " << std::setprecision(5) << r.time_of_arrival_s << "  " << std::setw(8)
        << std::setprecision(2) << decibels(r.level / direct) << "  " << std::setw(11) << degrees(r.azimuth_rad)
        << "  " << std::setw(13) << degrees(r.elevation_rad) << "  " << std::setw(10) << r.distance_m << "  "
        << std::setw(10) << r.confidence.value_or(-1.0) << "\n";
  }
  // A bent band's two slopes as T60s, the second's share of the energy at the mixing time.
  out << "late reverb (level re the direct sound):\n  band_hz   t60_s  level_db  two slopes: t60_s, share  reliable\n";
  for (const LateReverbBand& b : rsao.late.bands) {
    char slopes[64] = "-";
    if (hasTwoSlopes(b)) {
      std::snprintf(slopes, sizeof slopes, "%.3f %.3f %.1f %%", 3.0 * std::log(10.0) / b.first_decay_constant_per_s,
                    3.0 * std::log(10.0) / b.second_decay_constant_per_s, 100.0 * b.second_share);
    }
    out << std::setw(9) << std::setprecision(0) << b.center_hz << "  " << std::setprecision(3) << std::setw(6)
        << b.t60_s << "  " << std::setw(8) << std::setprecision(2) << decibels(b.level / direct) << "  "
        << std::setw(25) << slopes << "  " << (b.reliable ? "yes" : "no: " + b.reason) << "\n";
  }
}

// The RSAO at another listener position (--move-to), with or without a room model.
Rsao movedRsao(const Rsao& measured, const Eigen::Vector3d& listener, const std::optional<Eigen::Vector3d>& rig,
               const Arguments& args) {
  std::optional<RoomModel> room;
  if (args.has("room")) room = loadRoomModel(args.value("room", ""));
  if (!rig && !room) throw UsageError("--move-to needs the microphone's position: --rig X Y Z or --room ROOM.yaml");
  const Eigen::Vector3d rig_position = rig ? *rig : room->rig_position_m;
  const Eigen::Quaterniond rig_rotation = room && !rig ? room->rig_rotation : Eigen::Quaterniond::Identity();
  const ListenerTranslation translation(measured, rig_position, rig_rotation, room);
  const Rsao moved = translation.at(listener);
  std::size_t counts[5] = {0, 0, 0, 0, 0};
  for (const AnchoredReflection& a : translation.anchors()) ++counts[static_cast<int>(a.anchor)];
  std::cout << std::fixed << std::setprecision(3) << "moved from (" << rig_position.x() << ", " << rig_position.y()
            << ", " << rig_position.z() << ") to (" << listener.x() << ", " << listener.y() << ", " << listener.z()
            << ") m; source at (" << translation.sourcePosition().x() << ", " << translation.sourcePosition().y()
            << ", " << translation.sourcePosition().z() << ") m\n";
  if (room) {
    std::cout << "reflections: " << counts[static_cast<int>(ReflectionAnchor::kSurface)] << " matched to the room model, "
              << counts[static_cast<int>(ReflectionAnchor::kUnmatched)] << " unmatched (fading), "
              << counts[static_cast<int>(ReflectionAnchor::kModelled)] << " added from it; "
              << moved.reflections.size() - 1 << " heard at the new position\n";
  } else {
    std::cout << "reflections: " << measured.reflections.size() - 1
              << " moved as measured image sources (no room model to check them against)\n";
  }
  return moved;
}

int runRsao(const std::vector<std::string>& raw) {
  std::vector<std::string> rest = raw;
  const std::optional<Eigen::Vector3d> move_to = takeVector(rest, "move-to");
  const std::optional<Eigen::Vector3d> rig = takeVector(rest, "rig");
  const Arguments args(rest, {"format", "yaml", "visr-json", "resynthesis", "max-reflections", "window-ms", "lpc-order",
                              "mixing-time", "source-distance", "room"},
                       {"grid", "paper-ramp", "one-slope", "paper-onsets", "paper-lpc"});
  if (!move_to && (rig || args.has("room"))) throw UsageError("--rig and --room go with --move-to X Y Z");
  if (args.positional().size() != 1) throw UsageError("give exactly one B-format RIR file");
  if (!args.has("format")) throw UsageError("--format fuma|ambix is required: the file's convention is never guessed");
  const AmbisonicFormat format = parseAmbisonicFormat(args.value("format", ""));

  RsaoOptions options;
  const int max_reflections = args.intValue("max-reflections", static_cast<int>(options.early.max_reflections));
  if (max_reflections < 0) throw UsageError("--max-reflections must be 0 or more");
  options.early.max_reflections = static_cast<std::size_t>(max_reflections);
  options.early.analysis_window_s = args.doubleValue("window-ms", 2.0) / 1000.0;
  options.early.lpc_order = args.intValue("lpc-order", options.early.lpc_order);
  if (args.has("mixing-time")) options.mixing_time_s = args.doubleValue("mixing-time", 0.0);
  if (args.has("source-distance")) {
    options.early.direct_distance_m = args.doubleValue("source-distance", 0.0);
    if (!(*options.early.direct_distance_m > 0.0)) throw UsageError("--source-distance must be a positive distance in m");
  }
  if (args.has("grid") && !args.has("paper-onsets")) {
    throw UsageError("--grid goes with --paper-onsets: matching pursuit takes each direction from its arrival's own projection");
  }
  if (args.has("grid")) options.early.direction_method = DirectionMethod::kGridSearch;
  if (args.has("paper-onsets")) options.early.onset_method = OnsetMethod::kGroupDelay;
  if (args.has("paper-lpc")) options.early.lpc_flat_below_hz = 0.0;
  options.fit_onset_ramps = !args.has("paper-ramp");
  options.late.two_slopes = !args.has("one-slope");

  const AudioBuffer rir = readAudioFile(args.positional().front());
  const Rsao estimated = estimateRsao(rir, format, options);
  const Rsao rsao = move_to ? movedRsao(estimated, *move_to, rig, args) : estimated;
  // Everything is computed before anything is written, so bad input leaves no partial files.
  const std::string visr = args.has("visr-json") ? rsaoToVisrJson(rsao) : "";
  AudioBuffer resynthesis;
  if (args.has("resynthesis")) {
    ResynthesisOptions resynthesis_options;
    resynthesis_options.analysis_window_s = options.early.analysis_window_s;
    resynthesis = resynthesizeRsao(rsao, resynthesis_options);
  }
  if (args.has("yaml")) saveRsaoYaml(args.value("yaml", ""), rsao);
  if (args.has("visr-json")) writeTextFile(args.value("visr-json", ""), visr);
  if (args.has("resynthesis")) writeAudioFile(args.value("resynthesis", ""), resynthesis, SampleEncoding::kFloat32);

  for (const std::string& warning : rsao.warnings) std::cerr << "room_reverb rsao: warning: " << warning << "\n";
  printSummary(rsao, std::cout);
  return 0;
}

const CommandRegistration registration({"rsao", "parameterise a B-format RIR into a reverberant spatial audio object",
                                        kHelp, runRsao});

}  // namespace
}  // namespace room_reverb::tool
