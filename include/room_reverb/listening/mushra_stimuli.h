#pragma once
// The stimuli of a MUSHRA test: every dry content heard through every room and condition
// (mushra_room_responses.h), made comparable the way ITU-R BS.1534-3 asks (section 5.1
// and 5.2: equal loudness, no clicks, the same excerpt), so that listeners rate the room
// and not the level or the length:
//   1. every stimulus of a content is cut to one length (the plan's duration_s, else the
//      content's shortest stimulus; shorter ones are padded with silence, which is exact:
//      a render ends when its response does) with 10 ms raised-cosine fades at both ends;
//   2. each is brought to the plan's integrated loudness (ITU-R BS.1770, loudness.h);
//   3. if any sample of any stimulus then exceeds max_peak_dbfs, every stimulus of the
//      test is lowered by the same gain, so that they all stay equally loud.
// All stimuli are binaural (left, right) at 48 kHz.
#include <cstddef>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/listening/mushra_plan.h"

namespace room_reverb::core {

// Length of the fade-in and fade-out of every stimulus: long enough that the cut is no
// click, short enough to leave the reverberant onset and the tail's character alone.
constexpr double kMushraFadeS = 0.010;

struct MushraStimulus {
  std::string room;
  std::string content;
  std::string condition;
  AudioBuffer audio;           // binaural, 48 kHz, cut, faded, loudness-matched
  double loudness_lufs = 0.0;  // BS.1770 integrated loudness of `audio`, as measured
  double peak_dbfs = 0.0;      // its largest sample magnitude
};

struct MushraStimuli {
  // Room by room in plan order, then content, then condition (plan order).
  std::vector<MushraStimulus> stimuli;
  std::vector<double> content_duration_s;  // per plan content: the length of its stimuli
  double target_lufs = 0.0;                // the loudness every stimulus has
  double common_gain_db = 0.0;             // 0, or the gain that kept every peak under the limit
  std::vector<std::string> notes;          // from the renders, for the tool to print

  // InputError when there is no such stimulus.
  const MushraStimulus& find(const std::string& room, const std::string& content, const std::string& condition) const;
};

// Everything above for a plan. InputError for what the renders refuse (room and condition
// named), a dry content that is silent or shorter than 0.4 s, or a stimulus that ends up
// silent ("stimulus ROOM/CONTENT/CONDITION: silent").
MushraStimuli makeMushraStimuli(const MushraPlan& plan);

// `audio` cut to `frames` frames (padded with silence when shorter), then faded in over
// the first and out over the last `fade_s` seconds with raised-cosine (Hann) ramps.
AudioBuffer cutWithFades(const AudioBuffer& audio, std::size_t frames, double fade_s = kMushraFadeS);

}  // namespace room_reverb::core
