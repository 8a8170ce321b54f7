#pragma once
// The files of a MUSHRA test (`room_reverb mushra make --out DIR`), everything a test page
// needs and nothing it has to compute:
//
//   DIR/stimuli/<room>/<content>/<condition>.wav   binaural, 48 kHz, 32-bit float
//   DIR/panoramas/<room>.<ext>                      the rooms' panoramas, copied
//   DIR/test.json                                   scale, pages, letters, files (below)
//   DIR/plan_used.yaml                              the plan with every default filled in
//   DIR/webmushra.yaml                              the same test as a webMUSHRA config
//   DIR/index.html, mushra.js, mushra.css, test.js  the test page (mushra_page.h)
//   DIR/audio/<room>/<content>/<condition>.js       the stimuli as the page loads them
//
// Stimuli are 32-bit float WAV: no quantisation of the matched levels or of the tails'
// decay below -90 dBFS, and read by the Web Audio API's decodeAudioData in current
// browsers.
//
// test.json (paths relative to DIR; keys may be added, never renamed):
//   {"format": "room_reverb MUSHRA test", "version": 1, "seed": 7,
//    "scale": {"name": "0-5", "min": 0, "max": 5, "step": 1},
//    "sample_rate_hz": 48000, "loudness_lufs": -23.0, "max_peak_dbfs": -1.0, "fade_s": 0.01,
//    "conditions": [...], "hidden_anchors": [...], "shown_references": [...],
//    "attributes": [{"id", "question", "show_panorama"}], "rooms": [{"name", "panorama"}],
//    "contents": [{"name", "duration_s"}],
//    "results_columns": ["listener", "page", ...],   // the CSV the page saves (mushra analyze)
//    "pages": [{"id": "studio/speech/overall_quality", "room", "content", "attribute",
//               "question", "panorama": "panoramas/studio.jpg" or null, "duration_s",
//               "stimuli": [{"letter": "A", "condition", "file", "audio_script",
//                            "is_hidden_anchor", "is_shown_reference", "loudness_lufs",
//                            "peak_dbfs"}]}]}
#include <string>
#include <vector>

#include "room_reverb/listening/mushra_pages.h"
#include "room_reverb/listening/mushra_plan.h"
#include "room_reverb/listening/mushra_stimuli.h"

namespace room_reverb::core {

// Where a stimulus and a room's panorama go, relative to DIR.
std::string mushraStimulusFile(const std::string& room, const std::string& content, const std::string& condition);
std::string mushraPanoramaFile(const MushraRoom& room);  // "" when the room has none

// The text of DIR/test.json.
std::string mushraTestJson(const MushraPlan& plan, const MushraStimuli& stimuli, const std::vector<MushraPage>& pages);

// InputError unless `dir` can take a test: missing, empty, or holding an earlier test (a
// test.json). The tool calls it before rendering, so that a wrong --out costs no render.
void checkMushraOutputFolder(const std::string& dir);

// Writes every file above into `dir` (created if missing). A folder that already holds a
// test (a test.json) is replaced: its stimuli/, audio/ and panoramas/ folders are emptied
// first (results/, where `mushra serve` saves ratings, is kept),
// so no stimulus of an earlier plan is left behind. InputError for a `dir` that is a file,
// or a folder with other content and no test.json (not a test: nothing is overwritten),
// or a file that cannot be written.
void writeMushraTest(const MushraPlan& plan, const MushraStimuli& stimuli, const std::vector<MushraPage>& pages,
                     const std::string& dir);

}  // namespace room_reverb::core
