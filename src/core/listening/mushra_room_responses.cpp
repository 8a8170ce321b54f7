#include "room_reverb/listening/mushra_room_responses.h"

#include <memory>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/binaural/diffuse_field.h"
#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/binaural/rsao_binaural.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/rsao_estimator.h"

namespace room_reverb::core {
namespace {

// Makes the responses of one plan, keeping what several of them share.
class ResponseRenderer {
 public:
  explicit ResponseRenderer(const MushraPlan& plan) : plan_(plan), hrtf_(HrtfSet::loadSofa(plan.hrtf)) {
    for (const std::string& note : hrtf_.notes()) notes_.push_back("HRTF set: " + note);
  }

  MushraConditionResponse render(const MushraRoom& room, const std::string& condition) {
    if (condition == "reference") return {reference(room), 0.0};
    if (condition == "wrong_room") return {reference(plan_.room(room.wrong_room_of)), 0.0};
    if (condition == "lowpass_3k5") return {reference(room), kLowAnchorCutoffHz};
    if (condition == "rsao") return {rsao(room), 0.0};
    // The paper's "fast" condition is its Resonance-like renderer: image sources and an
    // Eyring tail (simulate --mode eyring).
    if (condition == "fast") return {simulated(room, SimulationMode::kEyring), 0.0};
    if (condition == "accurate") return {simulated(room, SimulationMode::kAccurate), 0.0};
    throw InputError("unknown MUSHRA condition '" + condition + "'");
  }

  std::vector<std::string>& notes() { return notes_; }

 private:
  // The measured RIR as AmbiX at 48 kHz.
  AudioBuffer measuredAmbix(const MushraRoom& room) {
    const AudioBuffer rir = readAudioFile(room.bformat_rir);
    if (rir.channelCount() != 4) {
      throw InputError(room.bformat_rir + ": a first-order B-format RIR has 4 channels, this one has " +
                       std::to_string(rir.channelCount()));
    }
    std::vector<std::string> notes;
    AudioBuffer ambix = ambixRoomResponse(rir, room.format == AmbisonicFormat::kFuMa ? "fuma" : "ambix", notes);
    for (const std::string& note : notes) notes_.push_back("room " + room.name + ": " + note);
    return ambix;
  }

  const AudioBuffer& reference(const MushraRoom& room) {
    auto found = references_.find(room.name);
    if (found == references_.end()) {
      const AudioBuffer ambix = measuredAmbix(room);
      found = references_.emplace(room.name, decode(ambix)).first;
    }
    return found->second;
  }

  AudioBuffer decode(const AudioBuffer& ambix) {
    const int order = binauralDecoderOrder(ambix);
    auto decoder = decoders_.find(order);
    if (decoder == decoders_.end()) decoder = decoders_.emplace(order, makeBinauralDecoder(hrtf_, order, plan_.decoder)).first;
    // A head facing +x of the response's frame, as `render` without --yaw.
    return binauralRoomResponse(ambix, decoder->second, Eigen::Quaterniond::Identity());
  }

  AudioBuffer rsao(const MushraRoom& room) {
    const Rsao object = estimateRsao(readAudioFile(room.bformat_rir), room.format);
    for (const std::string& warning : object.warnings) notes_.push_back("room " + room.name + ": RSAO: " + warning);
    // The diffuse-field spectrum of a dense set costs more than a late part: made once.
    if (!diffuse_field_) diffuse_field_ = std::make_unique<DiffuseFieldSpectrum>(diffuseFieldSpectrum(hrtf_));
    RsaoBinauralOptions options;
    options.resynthesis.seed = plan_.seed;
    return renderRsaoBinaural(object, hrtf_, *diffuse_field_, options);
  }

  AudioBuffer simulated(const MushraRoom& room, SimulationMode mode) {
    const RoomModel model = loadRoomModel(room.room_model);
    const AcousticScene scene = roomModelToScene(model, MaterialLibrary::loadDefault());
    SimulationSettings settings;
    settings.mode = mode;
    settings.image_source_order = plan_.simulation.image_source_order;
    settings.duration_s = plan_.simulation.duration_s;
    settings.ambisonic_order = plan_.simulation.ambisonic_order;
    settings.air = model.air;
    settings.rays.ray_count = static_cast<std::size_t>(plan_.simulation.rays);
    settings.rays.seed = plan_.seed;
    settings.rays.threads = plan_.simulation.threads;
    const SimulationResult result = simulateRoom(scene, *room.source_m, *room.listener_m, settings);
    if (result.stats.leaked_rays > 0) {
      notes_.push_back("room " + room.name + ": " + toString(mode) + " simulation: " +
                       std::to_string(result.stats.leaked_rays) + " rays leaked out of the room model");
    }
    return decode(result.impulse_response);
  }

  const MushraPlan& plan_;
  HrtfSet hrtf_;
  std::map<int, BinauralDecoder> decoders_;
  std::map<std::string, AudioBuffer> references_;
  std::unique_ptr<DiffuseFieldSpectrum> diffuse_field_;
  std::vector<std::string> notes_;
};

}  // namespace

const MushraConditionResponse& MushraRoomResponses::at(const std::string& room, const std::string& condition) const {
  const auto found = responses.find({room, condition});
  if (found == responses.end()) throw InputError("no response was rendered for room " + room + ", condition " + condition);
  return found->second;
}

MushraRoomResponses renderMushraRoomResponses(const MushraPlan& plan) {
  ResponseRenderer renderer(plan);
  MushraRoomResponses responses;
  for (const MushraRoom& room : plan.rooms) {
    for (const std::string& condition : plan.conditions) {
      try {
        responses.responses[{room.name, condition}] = renderer.render(room, condition);
      } catch (const InputError& e) {
        throw InputError("room " + room.name + ", condition " + condition + ": " + e.what());
      }
    }
  }
  responses.notes = std::move(renderer.notes());
  return responses;
}

}  // namespace room_reverb::core
