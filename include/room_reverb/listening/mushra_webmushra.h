#pragma once
// The test as a webMUSHRA configuration (AudioLabs Erlangen's browser MUSHRA software,
// https://github.com/audiolabs/webMUSHRA), for labs that already run their tests with it.
//
// How webMUSHRA's mushra page differs from ours, and what the export does about it:
// - its page has exactly one labelled reference, which it also adds as a hidden condition
//   named "reference" (and shuffles the conditions itself). The export gives it the plan's
//   first shown reference (or, with none, the `reference` condition, or else the first
//   condition) as `reference`, and the other conditions as `stimuli`, keyed by condition
//   name so that its results name conditions as ours do;
// - its own 3.5 and 7 kHz anchors are switched off (createAnchor35/70: false): the plan's
//   lowpass_3k5 is already a stimulus;
// - it rates on 0-100 only: a 0-5 plan is exported on 0-100 (a comment says so);
// - file paths are relative to webMUSHRA's own folder: the export assumes DIR is copied
//   into webMUSHRA's configs/ folder and opened as ?config=<DIR name>/webmushra.yaml.
// The pages are in one `random` group, so each listener meets them in a new order.
#include <string>
#include <vector>

#include "room_reverb/listening/mushra_pages.h"
#include "room_reverb/listening/mushra_plan.h"

namespace room_reverb::core {

// `folder_name`: the name of DIR, which the paths start with (configs/<folder_name>/...).
std::string webMushraConfigYaml(const MushraPlan& plan, const std::vector<MushraPage>& pages,
                                const std::string& folder_name);

}  // namespace room_reverb::core
