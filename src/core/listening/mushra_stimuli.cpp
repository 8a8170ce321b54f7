#include "room_reverb/listening/mushra_stimuli.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/audio/loudness.h"
#include "room_reverb/audio/lowpass_filter.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/common/error.h"
#include "room_reverb/listening/mushra_room_responses.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string stimulusName(const std::string& room, const std::string& content, const std::string& condition) {
  return "stimulus " + room + "/" + content + "/" + condition;
}

float peakOf(const AudioBuffer& audio) {
  float peak = 0.0f;
  for (const auto& channel : audio.channels) {
    for (float v : channel) peak = std::max(peak, std::abs(v));
  }
  return peak;
}

void scale(AudioBuffer& audio, double gain) {
  for (auto& channel : audio.channels) {
    for (float& v : channel) v = static_cast<float>(v * gain);
  }
}

// The number of frames every stimulus of one content gets: the plan's duration, or the
// shortest of the content's renders (each is the dry length plus its response's, less 1).
std::size_t contentFrames(const MushraPlan& plan, const AudioBuffer& dry, const MushraRoomResponses& responses) {
  if (plan.duration_s) return static_cast<std::size_t>(std::lround(*plan.duration_s * kInternalSampleRateHz));
  std::size_t shortest = 0;
  for (const auto& entry : responses.responses) {
    const std::size_t frames = dry.frameCount() + entry.second.brir.frameCount() - 1;
    shortest = shortest == 0 ? frames : std::min(shortest, frames);
  }
  return shortest;
}

}  // namespace

AudioBuffer cutWithFades(const AudioBuffer& audio, std::size_t frames, double fade_s) {
  AudioBuffer out;
  out.sample_rate_hz = audio.sample_rate_hz;
  const std::size_t fade = std::min(frames / 2, static_cast<std::size_t>(std::lround(fade_s * audio.sample_rate_hz)));
  for (const std::vector<float>& channel : audio.channels) {
    std::vector<float> cut(frames, 0.0f);
    std::copy_n(channel.begin(), std::min(frames, channel.size()), cut.begin());
    for (std::size_t n = 0; n < fade; ++n) {
      // Hann half-window: 0 before the first sample, 1 after the last of the ramp.
      const double ramp = 0.5 - 0.5 * std::cos(kPi * (static_cast<double>(n) + 0.5) / static_cast<double>(fade));
      cut[n] = static_cast<float>(cut[n] * ramp);
      cut[frames - 1 - n] = static_cast<float>(cut[frames - 1 - n] * ramp);
    }
    out.channels.push_back(std::move(cut));
  }
  return out;
}

const MushraStimulus& MushraStimuli::find(const std::string& room, const std::string& content,
                                          const std::string& condition) const {
  for (const MushraStimulus& s : stimuli) {
    if (s.room == room && s.content == content && s.condition == condition) return s;
  }
  throw InputError("no " + stimulusName(room, content, condition));
}

MushraStimuli makeMushraStimuli(const MushraPlan& plan) {
  // The dry contents first: a silent or unreadable one is found before any rendering.
  std::vector<AudioBuffer> dry;
  std::vector<std::string> notes;
  for (const MushraContent& content : plan.contents) {
    dry.push_back(loadDrySource(content.file, notes));
    integratedLoudnessLufs(dry.back(), "content " + content.name + " (" + content.file + ")");
  }
  const MushraRoomResponses responses = renderMushraRoomResponses(plan);

  MushraStimuli result;
  result.target_lufs = plan.loudness_lufs;
  result.notes = notes;
  result.notes.insert(result.notes.end(), responses.notes.begin(), responses.notes.end());
  std::vector<std::size_t> content_frames;
  for (std::size_t c = 0; c < plan.contents.size(); ++c) {
    content_frames.push_back(contentFrames(plan, dry[c], responses));
    result.content_duration_s.push_back(content_frames.back() / kInternalSampleRateHz);
  }
  for (const MushraRoom& room : plan.rooms) {
    for (std::size_t c = 0; c < plan.contents.size(); ++c) {
      const std::size_t frames = content_frames[c];
      for (const std::string& condition : plan.conditions) {
        MushraStimulus s{room.name, plan.contents[c].name, condition, {}, 0.0, 0.0};
        const std::string name = stimulusName(s.room, s.content, s.condition);
        const MushraConditionResponse& response = responses.at(room.name, condition);
        // convolveBinaural may lower a peak above full scale; the level is set below anyway.
        AudioBuffer rendered = convolveBinaural(dry[c], response.brir).audio;
        if (response.stimulus_lowpass_hz > 0.0) rendered = lowpassFiltered(rendered, response.stimulus_lowpass_hz);
        s.audio = cutWithFades(rendered, frames);
        scale(s.audio, loudnessMatchingGain(integratedLoudnessLufs(s.audio, name), plan.loudness_lufs));
        result.stimuli.push_back(std::move(s));
      }
    }
  }

  // One gain for the whole test, so that stimuli stay equally loud across pages too.
  float peak = 0.0f;
  for (const MushraStimulus& s : result.stimuli) peak = std::max(peak, peakOf(s.audio));
  const double limit = std::pow(10.0, plan.max_peak_dbfs / 20.0);
  if (peak > limit) {
    const double gain = limit / peak;
    result.common_gain_db = 20.0 * std::log10(gain);
    result.target_lufs += result.common_gain_db;
    for (MushraStimulus& s : result.stimuli) scale(s.audio, gain);
  }
  for (MushraStimulus& s : result.stimuli) {
    s.loudness_lufs = integratedLoudnessLufs(s.audio, stimulusName(s.room, s.content, s.condition));
    s.peak_dbfs = 20.0 * std::log10(std::max(peakOf(s.audio), 1e-30f));
  }
  return result;
}

}  // namespace room_reverb::core
