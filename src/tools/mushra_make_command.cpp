// room_reverb mushra make: a MUSHRA test from a plan: every stimulus
// rendered, cut, faded and loudness-matched, letters shuffled per page, and the files a
// test page reads written to one folder.
#include <algorithm>
#include <iomanip>
#include <iostream>

#include "arguments.h"
#include "command.h"
#include "mushra_steps.h"
#include "room_reverb/listening/mushra_pages.h"
#include "room_reverb/listening/mushra_plan.h"
#include "room_reverb/listening/mushra_stimuli.h"
#include "room_reverb/listening/mushra_test_files.h"

namespace room_reverb::tool {

using namespace room_reverb::core;

const char* const kMushraMakeHelp = R"(usage: room_reverb mushra make --plan PLAN.yaml --out DIR

make: renders a MUSHRA test from a plan (YAML): rooms (a measured B-format RIR with its
format fuma|ambix, and/or a room model with source_m and listener_m; an optional
panorama), dry contents, attributes with their questions, the conditions of every page
(reference, rsao, fast, accurate, wrong_room, lowpass_3k5), hidden_anchors,
shown_references, a seed, and optionally scale (0-5 or 0-100), duration_s,
loudness_lufs (-23), max_peak_dbfs (-1), hrtf, decoder and simulation settings
(include/room_reverb/listening/mushra_plan.h documents every key). Every stimulus is the
dry content heard binaurally through a room and condition, as `room_reverb render`
makes it; the stimuli of a content are cut to one length (duration_s, else the shortest)
with 10 ms raised-cosine fades, matched to the same ITU-R BS.1770 integrated loudness
(libebur128), and lowered together if any sample would exceed max_peak_dbfs. Pages are
room x content x attribute; letters are shuffled per page, fixed by the seed.
Writes DIR/stimuli/<room>/<content>/<condition>.wav (binaural, 48 kHz, 32-bit float),
DIR/panoramas/, DIR/test.json (what the test page reads), DIR/plan_used.yaml,
DIR/webmushra.yaml (the test as a webMUSHRA configuration) and the test page:
DIR/index.html with mushra.js, mushra.css, test.js and audio/ (the stimuli as scripts),
which works opened from the file system or served by `room_reverb mushra serve DIR`. A
DIR that holds an earlier test is replaced (results/ is kept); a non-empty DIR without a
test.json is refused.

  --plan FILE          the test plan (relative paths in it are relative to its folder)
  --out DIR            output folder (created if missing; required)

)";

int runMushraMake(const std::vector<std::string>& raw) {
  const Arguments args(raw, {"plan", "out"}, {});
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (!args.has("plan")) throw UsageError("--plan PLAN.yaml is required");
  if (!args.has("out")) throw UsageError("--out DIR is required");

  const MushraPlan plan = loadMushraPlan(args.value("plan", ""));
  checkMushraOutputFolder(args.value("out", ""));
  const MushraStimuli stimuli = makeMushraStimuli(plan);
  const std::vector<MushraPage> pages = mushraPages(plan);
  writeMushraTest(plan, stimuli, pages, args.value("out", ""));

  for (const std::string& note : stimuli.notes) std::cout << "room_reverb mushra make: note: " << note << "\n";
  double quietest = stimuli.stimuli.front().loudness_lufs, loudest = quietest;
  for (const MushraStimulus& s : stimuli.stimuli) {
    quietest = std::min(quietest, s.loudness_lufs);
    loudest = std::max(loudest, s.loudness_lufs);
  }
  std::cout << std::fixed << std::setprecision(2) << "wrote " << pages.size() << " pages of "
            << plan.conditions.size() << " stimuli (" << stimuli.stimuli.size() << " files) to "
            << args.value("out", "") << ": loudness " << quietest << " .. " << loudest << " LUFS";
  if (stimuli.common_gain_db < 0.0) {
    std::cout << " (target " << plan.loudness_lufs << " lowered by " << -stimuli.common_gain_db
              << " dB to keep every peak under " << plan.max_peak_dbfs << " dBFS)";
  }
  std::cout << "\ntest page: " << args.value("out", "") << "/index.html (open it in a browser, or run room_reverb "
            << "mushra serve " << args.value("out", "") << ")\n";
  return 0;
}

}  // namespace room_reverb::tool
