// room_reverb render: a dry source heard in a room over headphones, offline (the twin of
// the binaural_renderer node's ~render_to_file).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <set>

#include "arguments.h"
#include "command.h"
#include "simulation_arguments.h"
#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/binaural/rsao_binaural.h"
#include "room_reverb/binaural/walk_render.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/simulated_walk.h"
#include "room_reverb/rsao/listener_translation.h"
#include "room_reverb/rsao/rsao_yaml.h"
#include "room_reverb/common/error.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb render --source DRY.wav
                          (--bformat-rir F --format fuma|ambix | --ambisonic-rir F | --rsao F.yaml)
                          [--hrtf F.sofa] [--decoder magls|least_squares|virtual_loudspeakers]
                          [--yaw DEG] --out OUT.wav
       room_reverb render --source DRY.wav --rsao F.yaml --poses POSES.csv
                          (--room ROOM.yaml [--rig X Y Z] | --rig X Y Z) [--hrtf F.sofa]
                          [--decoder NAME] --out OUT.wav
       room_reverb render --source DRY.wav --room ROOM.yaml --source-at X Y Z
                          --poses POSES.csv [simulation options] [--hrtf F.sofa]
                          [--decoder NAME] --out OUT.wav

Renders a dry source in a room for headphones: the room's ambisonic impulse response,
turned for the listener's head, decoded to the two ears with an HRTF set, convolved with
the source. Writes a 2-channel (left, right) 32-bit float WAV at 48 kHz.

  --source FILE         the dry (anechoic) source; several channels are mixed to mono
  --bformat-rir FILE    a measured first-order B-format RIR (the paper's reference)
  --format F            its convention, fuma or ambix (required with --bformat-rir)
  --ambisonic-rir FILE  a simulated AmbiX RIR of order 0-3 (room_reverb simulate --out)
  --rsao FILE           an RSAO (room_reverb rsao --yaml): the direct sound and each
                        reflection through the HRTF of its direction, the late reverb as
                        band noise with the HRTF set's diffuse-field coherence per ear
  --hrtf FILE           SOFA SimpleFreeFieldHRIR set (default: the bundled KU100,
                        data/hrtf/FHK_HRIR_L2354.sofa); other rates are resampled
  --decoder NAME        magls (default), least_squares or virtual_loudspeakers (not
                        used with --rsao)
  --yaw DEG             the head turned DEG degrees to the left (counter-clockwise seen
                        from above); default 0: facing +x
  --poses FILE          a listener walking: CSV with the header t_s,x_m,y_m,z_m,qx,qy,qz,qw
                        (time, position in the room frame, orientation), poses between rows
                        interpolated. With --rsao: its late part convolved, its direct sound
                        and early reflections moved to the listener every 5.3 ms block, as
                        the binaural_renderer node plays a walkable room (docs/six_dof.md)
  --room FILE           with --poses: the room model the RSAO was measured in (its rig pose
                        the microphone's); reflections leave where their walls end
  --rig X Y Z           with --poses: the microphone's position (room frame), instead of
                        the room model's, or without a room model
  --source-at X Y Z     with --room and --poses, without --rsao: the simulated route
                        walked. The room is simulated once at the first pose (its late
                        part kept); the image sources (direct sound and reflections up to
                        --order) are computed again at the listener every 10.7 ms and
                        crossfaded in. Simulation options as for simulate (--mode,
                        --order, --rays, --seed, --threads, --duration, --materials,
                        --no-air, --temperature, --humidity, --scattering,
                        --receiver-radius; the ambisonic order is the decoder's, 3)
Exit status: 0 on success, 2 with one line on stderr for bad input.
)";

AudioBuffer monoSource(const std::string& path) {
  std::vector<std::string> notes;
  AudioBuffer source = loadDrySource(path, notes);
  for (const std::string& note : notes) std::cout << "room_reverb render: note: " << note << "\n";
  return source;
}

// The room's AmbiX response at 48 kHz.
AudioBuffer roomResponse(const Arguments& args) {
  std::vector<std::string> notes;
  AudioBuffer response;
  if (args.has("bformat-rir")) {
    if (!args.has("format")) throw UsageError("--format fuma|ambix is required with --bformat-rir");
    const std::string format = args.value("format", "");
    parseAmbisonicFormat(format);
    response = readAudioFile(args.value("bformat-rir", ""));
    if (response.channelCount() != 4) {
      throw InputError(args.value("bformat-rir", "") + ": a first-order B-format RIR has 4 channels, this one has " +
                       std::to_string(response.channelCount()));
    }
    response = ambixRoomResponse(response, format, notes);
  } else {
    response = ambixRoomResponse(readAudioFile(args.value("ambisonic-rir", "")), "ambix", notes);
  }
  for (const std::string& note : notes) std::cout << "room_reverb render: note: " << note << "\n";
  return response;
}

// A walk's render written as float WAV, a peak above full scale brought to -1 dBFS first
// (as every render for listening is).
void writeWalk(const std::string& path, AudioBuffer& out) {
  float peak = 0.0f;
  bool finite = true;
  for (const auto& channel : out.channels) {
    for (float v : channel) {
      finite = finite && std::isfinite(v);
      peak = std::max(peak, std::abs(v));
    }
  }
  if (!finite) {
    throw InputError("the walk's render overflows 32-bit float: the source holds values far beyond full scale "
                     "(is the file corrupt?)");
  }
  if (peak > 1.0f) {
    const float gain = std::pow(10.0f, -1.0f / 20.0f) / peak;
    for (auto& channel : out.channels)
      for (float& v : channel) v *= gain;
    std::cout << "room_reverb render: note: the peak was above full scale; scaled by " << 20.0 * std::log10(gain)
              << " dB to -1 dBFS\n";
  }
  writeAudioFile(path, out, SampleEncoding::kFloat32);
}

// A listener walking along --poses through a walkable RSAO.
int runWalk(const Arguments& args, const std::optional<Eigen::Vector3d>& rig) {
  if (!args.has("rsao")) throw UsageError("--poses needs --rsao F.yaml (a walk moves the RSAO's reflections)");
  if (args.has("yaw")) throw UsageError("--yaw and --poses do not go together: the poses turn the head");
  std::optional<RoomModel> room;
  if (args.has("room")) room = loadRoomModel(args.value("room", ""));
  if (!room && !rig) throw UsageError("--poses needs the microphone's position: --room ROOM.yaml or --rig X Y Z");
  const std::vector<ListenerPose> poses = loadPoseCsv(args.value("poses", ""));
  const DecoderMethod method = parseDecoderMethod(args.value("decoder", "magls"));
  const Rsao rsao = loadRsaoYaml(args.value("rsao", ""));
  const ListenerTranslation translation(rsao, rig ? *rig : room->rig_position_m,
                                        room && !rig ? room->rig_rotation : Eigen::Quaterniond::Identity(), room);
  // Every pose checked before the long work starts.
  for (const ListenerPose& pose : poses) translation.reflectionsAt(pose.position_m);
  const AudioBuffer source = monoSource(args.value("source", ""));
  const HrtfSet hrtf = HrtfSet::loadSofa(args.value("hrtf", HrtfSet::defaultSofaPath()));
  for (const std::string& note : hrtf.notes()) std::cout << "room_reverb render: note: " << note << "\n";
  AudioBuffer out = renderWalk(source, translation, makeBinauralDecoder(hrtf, 3, method), poses);
  writeWalk(args.value("out", ""), out);
  std::cout << "wrote " << args.value("out", "") << ": " << out.durationS() << " s, binaural, a listener walking "
            << poses.size() << " poses over " << poses.back().t_s - poses.front().t_s << " s\n";
  return 0;
}

// The simulated route walked along --poses from a room model and a source position.
int runSimulatedWalk(const Arguments& args, const Eigen::Vector3d& source_at) {
  if (!args.has("room")) throw UsageError("--source-at needs --room ROOM.yaml (the room the source is simulated in)");
  if (!args.has("poses")) throw UsageError("--source-at needs --poses POSES.csv (where the listener walks)");
  if (args.has("yaw")) throw UsageError("--yaw and --poses do not go together: the poses turn the head");
  const std::vector<ListenerPose> poses = loadPoseCsv(args.value("poses", ""));
  const DecoderMethod method = parseDecoderMethod(args.value("decoder", "magls"));
  SimulationSettings settings = simulationSettingsFrom(args);
  if (args.has("ambisonic-order")) throw UsageError("--ambisonic-order is the decoder's (3) in a walk");
  settings.ambisonic_order = 3;
  AirConditions air;
  AcousticScene scene = sceneFrom(SceneFiles{args.value("room", ""), "", UpAxis::kZ, false}, args, air);
  settings.air = air;
  const SimulatedWalk walk(std::move(scene), source_at, poses.front().position_m, settings);
  const AudioBuffer source = monoSource(args.value("source", ""));
  const HrtfSet hrtf = HrtfSet::loadSofa(args.value("hrtf", HrtfSet::defaultSofaPath()));
  for (const std::string& note : hrtf.notes()) std::cout << "room_reverb render: note: " << note << "\n";
  AudioBuffer out = renderSimulatedWalk(source, walk, makeBinauralDecoder(hrtf, 3, method), poses);
  writeWalk(args.value("out", ""), out);
  std::cout << "wrote " << args.value("out", "") << ": " << out.durationS() << " s, binaural, the simulated room ("
            << toString(settings.mode) << ") walked through " << poses.size() << " poses over "
            << poses.back().t_s - poses.front().t_s << " s\n";
  return 0;
}

int runRender(const std::vector<std::string>& raw) {
  std::vector<std::string> rest = raw;
  const std::optional<Eigen::Vector3d> rig = takeVector(rest, "rig");
  const std::optional<Eigen::Vector3d> source_at = takeVector(rest, "source-at");
  std::set<std::string> options = {"source", "bformat-rir", "format", "ambisonic-rir", "rsao", "hrtf", "decoder",
                                   "yaw", "out", "poses", "room"};
  std::set<std::string> flags;
  if (source_at) {
    options.merge(simulationValueOptions());
    flags = simulationFlags();
  }
  const Arguments args(rest, options, flags);
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (!args.has("source")) throw UsageError("--source DRY.wav is required");
  if (!args.has("out")) throw UsageError("--out OUT.wav is required");
  if (source_at) {
    if (args.has("bformat-rir") || args.has("ambisonic-rir") || args.has("rsao") || rig) {
      throw UsageError("--source-at simulates the room: no --bformat-rir, --ambisonic-rir, --rsao or --rig with it");
    }
    return runSimulatedWalk(args, *source_at);
  }
  if (int(args.has("bformat-rir")) + int(args.has("ambisonic-rir")) + int(args.has("rsao")) != 1) {
    throw UsageError("give exactly one of --bformat-rir, --ambisonic-rir and --rsao");
  }
  if (args.has("poses")) return runWalk(args, rig);
  if (rig || args.has("room")) throw UsageError("--room and --rig go with --poses");
  const double yaw_deg = args.doubleValue("yaw", 0.0);
  if (!std::isfinite(yaw_deg)) throw UsageError("--yaw must be a finite number of degrees");
  const DecoderMethod method = parseDecoderMethod(args.value("decoder", "magls"));

  const AudioBuffer source = monoSource(args.value("source", ""));
  const Eigen::Quaterniond head(Eigen::AngleAxisd(yaw_deg * 3.14159265358979323846 / 180.0, Eigen::Vector3d::UnitZ()));
  const std::optional<Rsao> rsao = args.has("rsao") ? std::optional<Rsao>(loadRsaoYaml(args.value("rsao", ""))) : std::nullopt;
  const AudioBuffer response = rsao ? AudioBuffer{} : roomResponse(args);
  const HrtfSet hrtf = HrtfSet::loadSofa(args.value("hrtf", HrtfSet::defaultSofaPath()));
  for (const std::string& note : hrtf.notes()) std::cout << "room_reverb render: note: " << note << "\n";
  AudioBuffer brir;
  std::string how;
  if (rsao) {
    RsaoBinauralOptions options;
    options.head_in_rig = head.toRotationMatrix();
    brir = renderRsaoBinaural(*rsao, hrtf, options);
    how = "RSAO through the HRTFs";
  } else {
    const int order = binauralDecoderOrder(response);
    brir = binauralRoomResponse(response, makeBinauralDecoder(hrtf, order, method), head);
    how = "order-" + std::to_string(order) + " " + toString(method) + " decoder";
  }
  const BinauralRender render = convolveBinaural(source, brir);
  if (render.gain_db < 0.0) {
    std::cout << "room_reverb render: note: the peak was above full scale; scaled by " << render.gain_db
              << " dB to -1 dBFS\n";
  }
  const AudioBuffer& out = render.audio;
  writeAudioFile(args.value("out", ""), out, SampleEncoding::kFloat32);
  std::cout << "wrote " << args.value("out", "") << ": " << out.durationS() << " s, binaural, " << how << ", peak "
            << render.peak_dbfs << " dBFS\n";
  return 0;
}

const CommandRegistration registration({"render", "render a dry source in a room for headphones (binaural)", kHelp,
                                        runRender});

}  // namespace
}  // namespace room_reverb::tool
